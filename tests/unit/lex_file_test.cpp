// The one NOME lexer as the formatter and the editor features see it (`lex_file`): token
// kinds and byte ranges, comments kept, and the forgiveness an editor buffer needs (an
// unclosed comment, function or string is one token to where it would end).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "frontend/parse/parse.h"

namespace nomec {
namespace {

// "Kind:text" per token.
std::vector<std::string> tokens(std::string_view text) {
  std::vector<std::string> out;
  for (const LexToken& t : lex_file(text)) {
    std::string k;
    switch (t.kind) {
      case LexKind::Word: k = "W"; break;
      case LexKind::Number: k = "N"; break;
      case LexKind::DollarRef: k = "$"; break;
      case LexKind::String: k = "S"; break;
      case LexKind::Raw: k = "R"; break;
      case LexKind::TclInit: k = "T"; break;
      case LexKind::LParen: k = "("; break;
      case LexKind::RParen: k = ")"; break;
      case LexKind::LBrace: k = "{"; break;
      case LexKind::RBrace: k = "}"; break;
      case LexKind::Comma: k = ","; break;
      case LexKind::Operator: k = "O"; break;
      case LexKind::LineComment: k = "#"; break;
      case LexKind::BlockComment: k = "C"; break;
      case LexKind::Other: k = "?"; break;
    }
    out.push_back(k + ":" + std::string(text.substr(t.begin, t.end - t.begin)));
  }
  return out;
}

using V = std::vector<std::string>;

TEST(LexFile, KindsAndRanges) {
  EXPECT_EQ(tokens("point p (0 -0.5*$b.w 1e-3) endpoint # c"),
            (V{"W:point", "W:p", "(:(", "N:0", "O:-", "N:0.5", "O:*", "$:$b.w", "N:1e-3", "):)", "W:endpoint", "#:# c"}));
  EXPECT_EQ(tokens("funcX [cos(u)*v] (* a (* nested *) comment *) {expr 1 // 2}"),
            (V{"W:funcX", "R:[cos(u)*v]", "C:(* a (* nested *) comment *)", "{:{", "W:expr", "N:1", "O://", "N:2", "}:}"}));
  EXPECT_EQ(tokens("tclinit { set a {1} }\ninclude \"v.slf\""), (V{"T:tclinit { set a {1} }", "W:include", "S:\"v.slf\""}));
  // Byte offsets in text with non-ASCII characters.
  EXPECT_EQ(tokens("# é\np é"), (V{"#:# é", "W:p", "?:é"}));
}

TEST(LexFile, ForgivesWhatAnEditorBufferHolds) {
  EXPECT_EQ(tokens("p (* open\nq r"), (V{"W:p", "C:(* open\nq r"}));
  EXPECT_EQ(tokens("funcX [cos(u\nv"), (V{"W:funcX", "R:[cos(u\nv"}));
  EXPECT_EQ(tokens("include \"v.slf\nq"), (V{"W:include", "S:\"v.slf", "W:q"}));
  EXPECT_EQ(tokens("a %{ raw"), (V{"W:a", "R:%{ raw"}));
  EXPECT_EQ(tokens("a % b"), (V{"W:a", "O:%", "W:b"}));
  // Inside braces (Tcl text) a lone `[` is one character, as the parser reads it, not the
  // start of a function that runs to the end of the text.
  EXPECT_EQ(tokens("({si[1} 0)"), (V{"(:(", "{:{", "W:si", "?:[", "N:1", "}:}", "N:0", "):)"}));
}

TEST(LexFile, NoBreakSpaceSeparatesLikeASpace) {
  EXPECT_EQ(tokens("(1\xc2\xa0-2)"), (V{"(:(", "N:1", "O:-", "N:2", "):)"}));
}

}  // namespace
}  // namespace nomec
