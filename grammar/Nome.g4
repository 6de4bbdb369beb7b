// Nome.g4: the one grammar for NOME 2016 (`.nome`, `.anom`), NOME3 (`.nom`) and the SLIDE
// subset (`.slf`).
//
// Design: the grammar fixes *structure* exactly and leaves *meaning* to the front end.
// Every block statement is `keyword … endkeyword` with a strictly paired end keyword, so
// nesting is never guessed. A block body is a flat sequence of items (words, parenthesised
// lists, values) and the nested blocks that this kind of block may contain. Which words a
// command accepts, how many list elements it needs, and what they mean are checked by the
// front end (frontend/check), where the diagnostics can name the command, show how a list
// was split and suggest spellings. Keywords are contextual: any keyword can be used as a
// name (rule `keywordName`, or IDENT), except end keywords.
//
// Four token types are assigned after lexing by frontend/parse (not by this grammar), so the
// grammar stays target-neutral:
//  * K_GEN / E_GEN: a name that is a generator keyword of the catalogue, and its `end` form
//    (see `generatorStmt`).
//  * SPLUS / SMINUS: a `+`/`-` preceded by whitespace or `(` and directly followed by a
//    non-space character. At the top level of a list or block body it starts a new element
//    (language.md §3); inside parentheses, braces and call arguments it is an ordinary
//    binary operator wherever that reading is possible.
grammar Nome;

tokens { SPLUS, SMINUS, K_GEN, E_GEN }

// ---------------------------------------------------------------------------------------
// Parser
// ---------------------------------------------------------------------------------------

file : topStmt* EOF ;

// A top-level statement. `strayItem` lets a word or value outside any block reach the
// front end, which explains it (e.g. `set` outside a bank, a misspelt keyword) instead of
// an ANTLR message. A block keyword is never a stray word, so a damaged block is recovered
// inside its own rule and its error names the block.
topStmt : TCLINIT | includeStmt | block | strayItem ;

// SLIDE `include "viewing.slf"`: no end keyword.
includeStmt : K_INCLUDE STRING ;
strayItem : IDENT | K_EXPR | parenList | itemExpr ;

block
  : bankStmt | surfaceStmt | pointStmt | polylineStmt | faceStmt | facetStmt | vertexStmt
  | objectStmt | meshStmt | groupStmt | instanceStmt | sweepStmt | crosssectionStmt
  | pathStmt | controlpointStmt | transformStmt | lookatStmt | deleteStmt | sharpStmt
  | zipperStmt | mergeStmt | subdivisionStmt | offsetStmt | handleStmt | rindStmt
  | sierpinskiStmt | mengerStmt | mirrorStmt | savedparameterStmt | consolidateStmt
  | consolidatefaceStmt | savedworkingmeshStmt | cameraStmt | lightStmt | windowStmt
  | viewportStmt | renderStmt | displayStmt | frontcolorStmt | backcolorStmt | backgroundcolorStmt
  | backfaceStmt | sweepmorphStmt | morphvisualizerStmt | generatorStmt
  ;

// Blocks whose body is only items.
bankStmt            : K_BANK item* E_BANK ;
surfaceStmt         : K_SURFACE item* E_SURFACE ;
pointStmt           : K_POINT item* E_POINT ;
polylineStmt        : K_POLYLINE item* E_POLYLINE ;
facetStmt           : K_FACET item* E_FACET ;
vertexStmt          : K_VERTEX item* E_VERTEX ;
objectStmt          : K_OBJECT item* E_OBJECT ;
pathStmt            : K_PATH item* E_PATH ;
controlpointStmt    : K_CONTROLPOINT item* E_CONTROLPOINT ;
transformStmt       : K_TRANSFORM item* E_TRANSFORM ;
lookatStmt          : K_LOOKAT item* E_LOOKAT ;
sharpStmt           : K_SHARP item* E_SHARP ;
zipperStmt          : K_ZIPPER item* E_ZIPPER ;
savedparameterStmt  : K_SAVEDPARAMETER item* E_SAVEDPARAMETER ;
cameraStmt          : K_CAMERA item* E_CAMERA ;
lightStmt           : K_LIGHT item* E_LIGHT ;
windowStmt          : K_WINDOW item* E_WINDOW ;
viewportStmt        : K_VIEWPORT item* E_VIEWPORT ;
renderStmt          : K_RENDER item* E_RENDER ;
// NOME2 (2018) display colours.
displayStmt
  : K_FOREGROUND item* E_FOREGROUND | K_BACKGROUND item* E_BACKGROUND
  | K_INSIDEFACES item* E_INSIDEFACES | K_OUTSIDEFACES item* E_OUTSIDEFACES
  | K_OFFSETFACES item* E_OFFSETFACES
  ;
frontcolorStmt      : K_FRONTCOLOR item* E_FRONTCOLOR ;
backcolorStmt       : K_BACKCOLOR item* E_BACKCOLOR ;
backgroundcolorStmt : K_BACKGROUNDCOLOR item* E_BACKGROUNDCOLOR ;
backfaceStmt        : K_BACKFACE item* E_BACKFACE ;
morphvisualizerStmt : K_MORPHVISUALIZER item* E_MORPHVISUALIZER ;

// Blocks with nested blocks.
faceStmt            : K_FACE (vertexStmt | item)* E_FACE ;        // `.anom` faces list vertices
meshStmt            : K_MESH (pointStmt | faceStmt | sharpStmt | vertexStmt | facetStmt | item)* E_MESH ;
groupStmt           : K_GROUP (instanceStmt | item)* E_GROUP ;
instanceStmt        : K_INSTANCE (lookatStmt | item)* E_INSTANCE ;
sweepStmt           : K_SWEEP (crosssectionStmt | pathStmt | item)* E_SWEEP ;
sweepmorphStmt      : K_SWEEPMORPH (pathStmt | item)* E_SWEEPMORPH ;
crosssectionStmt    : K_CROSSSECTION (transformStmt | item)* E_CROSSSECTION ;
deleteStmt          : K_DELETE (faceStmt | item)* E_DELETE ;
consolidateStmt     : K_CONSOLIDATE (consolidatefaceStmt | item)* E_CONSOLIDATE ;
consolidatefaceStmt : K_CONSOLIDATEFACE (vertexStmt | item)* E_CONSOLIDATEFACE ;
savedworkingmeshStmt: K_SAVEDWORKINGMESH (faceStmt | item)* E_SAVEDWORKINGMESH ;

// Pipeline blocks contain instances and may nest further statements.
mergeStmt           : K_MERGE (block | item)* E_MERGE ;
subdivisionStmt     : K_SUBDIVISION (block | item)* E_SUBDIVISION ;
offsetStmt          : K_OFFSET (block | item)* E_OFFSET ;
handleStmt          : K_HANDLE (block | item)* E_HANDLE ;
rindStmt            : K_RIND (block | item)* E_RIND ;
sierpinskiStmt      : K_SIERPINSKI (block | item)* E_SIERPINSKI ;
mengerStmt          : K_MENGER (block | item)* E_MENGER ;
mirrorStmt          : K_MIRROR (block | item)* E_MIRROR ;

// Generators. Their keywords are not lexer rules: the generator catalogue
// (ir/generators.def) lists them, and frontend/parse retypes a name that is a catalogue
// keyword to K_GEN and `end` + keyword to E_GEN, so a new generator needs no grammar change.
// The front end checks that the end keyword closes the same generator (2016 files close
// `tunnel` with `endfunnel`; it warns about that).
generatorStmt : K_GEN item* E_GEN ;

// ----- Items: the flat contents of a block body -----
// Alternatives start with disjoint tokens, so no item needs more than one token of
// lookahead to choose its alternative.
// A name is IDENT or a `keywordName` (IDENT, the most frequent, needs no rule of its own).
item
  : (IDENT | keywordName)  # wordItem
  | parenList              # listItem
  | itemExpr               # valueItem
  ;

// `( e e e )`: space-separated elements (commas tolerated; the front end warns).
parenList : LPAREN (listExpr | COMMA)* RPAREN ;

// ----- Expressions -----
// An expression is a flat run of operands and operators: `sign* operand (op sign* operand)*`.
// The AST builder applies the precedence (loosest to tightest: `+ -`; `* / % //`; unary
// `+ -`; `^`, right-associative, whose right operand may carry signs: `-2^2` is −4, `2^-1`
// is 0.5), so the parse tree holds at most two nodes per operand instead of one per level.
// `expr` (nested contexts: calls, parentheses, braces) also takes `SPLUS`/`SMINUS` as
// binary operators; a list element (`listExpr`) ends before one (the sign rule).
// An operand is a NUMBER or DOLLAR_REF token (the most frequent operands: one tree node,
// no rule of their own) or an `atom`.
expr
  : (PLUS | MINUS | SPLUS | SMINUS)* (NUMBER | DOLLAR_REF | atom)
    ((PLUS | MINUS | SPLUS | SMINUS | STAR | SLASH | DSLASH | PERCENT | CARET) (PLUS | MINUS | SPLUS | SMINUS)* (NUMBER | DOLLAR_REF | atom))*
  ;
listExpr
  : (PLUS | MINUS | SPLUS | SMINUS)* (NUMBER | DOLLAR_REF | atom)
    ((PLUS | MINUS | STAR | SLASH | DSLASH | PERCENT | CARET) (PLUS | MINUS | SPLUS | SMINUS)* (NUMBER | DOLLAR_REF | atom))*
  ;
atom
  : TCL_ARRAY_REF                                   # tclArrayAtom
  | (IDENT | keywordName) LPAREN (expr (COMMA expr)*)? RPAREN   # callAtom
  | (IDENT | keywordName)                                        # nameAtom
  | LPAREN expr RPAREN                              # parenAtom
  | braceExpr                                       # braceAtom
  | BRACKET_RAW                                     # rawAtom
  | STRING                                          # stringAtom
  | PCT_RAW                                         # pctAtom
  ;

// A function text parsed on its own (`funcX [ cos(u)*v ]`): one expression, nothing after.
functionText : expr EOF ;

// A value in a block body: like `listExpr` but never starting with a bare word or `(`
// (those are the `word` and `parenList` items), which keeps `item` LL(1).
itemExpr
  : ((PLUS | MINUS | SPLUS | SMINUS)+ (NUMBER | DOLLAR_REF | atom) | NUMBER | DOLLAR_REF | itemAtom)
    ((PLUS | MINUS | STAR | SLASH | DSLASH | PERCENT | CARET) (PLUS | MINUS | SPLUS | SMINUS)* (NUMBER | DOLLAR_REF | atom))*
  ;
itemAtom
  : TCL_ARRAY_REF   # itemTclArray
  | braceExpr       # itemBrace
  | BRACKET_RAW     # itemRaw
  | STRING          # itemString
  | PCT_RAW         # itemPct
  ;

// `{expr …}` (Tcl heritage) or plain `{…}`; in SLIDE a brace value can also be a whole
// Tcl script (`lod {if {$n >= 2} {expr 1} else {expr 0}}`), kept raw for the front end.
braceExpr : LBRACE K_EXPR? expr RBRACE | tclBraces ;
tclBraces : LBRACE (tclBraces | ~(LBRACE | RBRACE))* RBRACE ;

// A name is an identifier (IDENT, written directly where a name may stand) or any
// contextual keyword: this rule.
keywordName
  : K_EXPR | K_INCLUDE
  | K_BANK | K_SURFACE | K_POINT | K_POLYLINE | K_FACE | K_FACET | K_VERTEX | K_OBJECT
  | K_MESH | K_GROUP | K_INSTANCE | K_SWEEP | K_CROSSSECTION | K_PATH | K_CONTROLPOINT
  | K_TRANSFORM | K_LOOKAT | K_DELETE | K_SHARP | K_ZIPPER | K_MERGE | K_SUBDIVISION
  | K_OFFSET | K_HANDLE | K_RIND | K_SIERPINSKI | K_MENGER | K_MIRROR | K_SAVEDPARAMETER
  | K_CONSOLIDATE | K_CONSOLIDATEFACE | K_SAVEDWORKINGMESH | K_CAMERA | K_LIGHT | K_WINDOW
  | K_VIEWPORT | K_RENDER | K_FRONTCOLOR | K_BACKCOLOR | K_BACKGROUNDCOLOR | K_BACKFACE
  | K_SWEEPMORPH | K_MORPHVISUALIZER | K_GEN
  | K_FOREGROUND | K_BACKGROUND | K_INSIDEFACES | K_OUTSIDEFACES | K_OFFSETFACES
  ;

// ---------------------------------------------------------------------------------------
// Lexer
// ---------------------------------------------------------------------------------------

// `tclinit { … }` is kept whole, braces balanced, as raw text with its range.
TCLINIT : ('tclinit' | 'tclupdate') [ \t\r\n]* TCL_BRACES ;
fragment TCL_BRACES : '{' ( TCL_BRACES | '\\' . | ~[{}\\] )* '}' ;

// Nested `(* … *)` block comments (SLIDE semantics). An unclosed one does not match this
// rule; the front end detects the `(` `*` pair and reports it at its opening.
BLOCK_COMMENT : '(*' ( BLOCK_COMMENT | . )*? '*)' -> channel(HIDDEN) ;
LINE_COMMENT  : '#' ~[\r\n]* -> channel(HIDDEN) ;
// U+FEFF is whitespace: a file some editors save starts with it (the UTF-8 byte order mark).
WS            : [ \t\r\n\f\u000B\uFEFF]+ -> channel(HIDDEN) ;
// U+00A0 (no-break space) separates tokens like a space: real files have it inside number
// lists, and every original tool skipped it (compat.md §B1). The front end warns.
NBSP          : '\u00A0'+ -> channel(HIDDEN) ;

K_EXPR : 'expr' ;
K_INCLUDE : 'include' ;
K_BANK : 'bank' ;                     E_BANK : 'endbank' ;
K_SURFACE : 'surface' ;               E_SURFACE : 'endsurface' ;
K_POINT : 'point' ;                   E_POINT : 'endpoint' ;
K_POLYLINE : 'polyline' ;             E_POLYLINE : 'endpolyline' ;
K_FACE : 'face' ;                     E_FACE : 'endface' ;
K_FACET : 'facet' ;                   E_FACET : 'endfacet' ;
K_VERTEX : 'vertex' ;                 E_VERTEX : 'endvertex' ;
K_OBJECT : 'object' ;                 E_OBJECT : 'endobject' ;
K_MESH : 'mesh' ;                     E_MESH : 'endmesh' ;
K_GROUP : 'group' ;                   E_GROUP : 'endgroup' ;
K_INSTANCE : 'instance' ;             E_INSTANCE : 'endinstance' ;
K_SWEEP : 'sweep' ;                   E_SWEEP : 'endsweep' ;
K_CROSSSECTION : 'crosssection' ;     E_CROSSSECTION : 'endcrosssection' ;
K_PATH : 'path' ;                     E_PATH : 'endpath' ;
K_CONTROLPOINT : 'controlpoint' ;     E_CONTROLPOINT : 'endcontrolpoint' ;
K_TRANSFORM : 'transform' ;           E_TRANSFORM : 'endtransform' ;
K_LOOKAT : 'lookat' ;                 E_LOOKAT : 'endlookat' ;
K_DELETE : 'delete' ;                 E_DELETE : 'enddelete' ;
K_SHARP : 'sharp' ;                   E_SHARP : 'endsharp' ;
K_ZIPPER : 'zipper' ;                 E_ZIPPER : 'endzipper' ;
K_MERGE : 'merge' ;                   E_MERGE : 'endmerge' ;
K_SUBDIVISION : 'subdivision' ;       E_SUBDIVISION : 'endsubdivision' ;
K_OFFSET : 'offset' ;                 E_OFFSET : 'endoffset' ;
K_HANDLE : 'handle' ;                 E_HANDLE : 'endhandle' ;
K_RIND : 'rind' ;                     E_RIND : 'endrind' ;
K_SIERPINSKI : 'sierpinski' ;         E_SIERPINSKI : 'endsierpinski' ;
K_MENGER : 'menger' ;                 E_MENGER : 'endmenger' ;
K_MIRROR : 'mirror' ;                 E_MIRROR : 'endmirror' ;
K_SAVEDPARAMETER : 'savedparameter' ; E_SAVEDPARAMETER : 'endsavedparameter' ;
K_CONSOLIDATE : 'consolidate' ;       E_CONSOLIDATE : 'endconsolidate' ;
K_CONSOLIDATEFACE : 'consolidateface' ;   E_CONSOLIDATEFACE : 'endconsolidateface' ;
K_SAVEDWORKINGMESH : 'savedworkingmesh' ; E_SAVEDWORKINGMESH : 'endsavedworkingmesh' ;
K_CAMERA : 'camera' ;                 E_CAMERA : 'endcamera' ;
K_LIGHT : 'light' ;                   E_LIGHT : 'endlight' ;
K_WINDOW : 'window' ;                 E_WINDOW : 'endwindow' ;
K_VIEWPORT : 'viewport' ;             E_VIEWPORT : 'endviewport' ;
K_RENDER : 'render' ;                 E_RENDER : 'endrender' ;
K_FOREGROUND : 'foreground' ;         E_FOREGROUND : 'endforeground' ;
K_BACKGROUND : 'background' ;         E_BACKGROUND : 'endbackground' ;
K_INSIDEFACES : 'insidefaces' ;       E_INSIDEFACES : 'endinsidefaces' ;
K_OUTSIDEFACES : 'outsidefaces' ;     E_OUTSIDEFACES : 'endoutsidefaces' ;
K_OFFSETFACES : 'offsetfaces' ;       E_OFFSETFACES : 'endoffsetfaces' ;
K_FRONTCOLOR : 'frontcolor' ;         E_FRONTCOLOR : 'endfrontcolor' ;
K_BACKCOLOR : 'backcolor' ;           E_BACKCOLOR : 'endbackcolor' ;
K_BACKGROUNDCOLOR : 'backgroundcolor' ; E_BACKGROUNDCOLOR : 'endbackgroundcolor' ;
K_BACKFACE : 'backface' ;             E_BACKFACE : 'endbackface' ;
K_SWEEPMORPH : 'sweepmorph' ;         E_SWEEPMORPH : 'endsweepmorph' ;
K_MORPHVISUALIZER : 'morphvisualizer' ; E_MORPHVISUALIZER : 'endmorphvisualizer' ;

NUMBER
  : DIGITS ('.' DIGITS?)? EXPONENT?
  | '.' DIGITS EXPONENT?
  ;
fragment DIGITS   : [0-9]+ ;
fragment EXPONENT : [eE] [+-]? DIGITS ;

// `$oSubdivision(type)`: a Tcl array element (SLIDE's slideui objects).
TCL_ARRAY_REF : '$' ID_START ID_PART* '(' [A-Za-z0-9_]* ')' ;
// `$bank.param`, `$bank_param`, `$time`.
DOLLAR_REF    : '$' ID_START ID_PART* ;
IDENT         : ID_START ID_PART* ;
fragment ID_START : [A-Za-z_.] ;
fragment ID_PART  : [A-Za-z0-9_.] ;

STRING      : '"' ( '\\' . | ~["\\\r\n] )* '"' ;
PCT_RAW     : '%{' .*? '}%' ;
BRACKET_RAW : '[' ( BRACKET_RAW | ~[[\]] )* ']' ;

DSLASH  : '//' ;
PLUS    : '+' ;
MINUS   : '-' ;
STAR    : '*' ;
SLASH   : '/' ;
PERCENT : '%' ;
CARET   : '^' ;
LPAREN  : '(' ;
RPAREN  : ')' ;
LBRACE  : '{' ;
RBRACE  : '}' ;
COMMA   : ',' ;

// Anything else becomes one token the front end reports as an unexpected character.
UNEXPECTED_CHAR : . ;
