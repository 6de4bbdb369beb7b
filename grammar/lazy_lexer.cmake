# Run by grammar/CMakeLists.txt on the generated NomeLexer.cpp (cmake -DFILE=… -P): the
# generated lexer builds its ATN (deserialised and verified) in a static initialiser, at
# the start of every program, although nomec lexes with its own lexer and constructs a
# NomeLexer only as the reference of the differential tests and as a fallback
# (frontend/parse). The ATN is built at the first construction instead: 6 M of the 27 M
# instructions of `nomec --check` on a 19 KiB example. Fails if the generated code is not
# the shape this expects.
file(READ "${FILE}" _text)
set(_static "NomeLexer::Initializer NomeLexer::_init;")
set(_ctor "NomeLexer::NomeLexer(CharStream *input) : Lexer(input) {")
string(FIND "${_text}" "${_static}" _at_static)
string(FIND "${_text}" "${_ctor}" _at_ctor)
if(_at_static EQUAL -1 OR _at_ctor EQUAL -1)
  message(FATAL_ERROR "lazy_lexer.cmake: ${FILE} does not have the generated lexer's static initialiser or constructor")
endif()
string(REPLACE "${_static}" "// (the ATN is built at the first construction: grammar/lazy_lexer.cmake)" _text "${_text}")
string(REPLACE "${_ctor}" "${_ctor}\n  static const Initializer once;  // grammar/lazy_lexer.cmake\n  (void)once;" _text "${_text}")
file(WRITE "${FILE}" "${_text}")
