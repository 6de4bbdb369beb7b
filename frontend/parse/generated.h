// The ANTLR-generated lexer and parser with the ANTLR runtime, for the parse layer's
// implementation files only: included here once, without the warnings their code raises
// under the project's flags.
#pragma once

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wall"
#pragma GCC diagnostic ignored "-Wextra"
#pragma GCC diagnostic ignored "-Wattributes"
#pragma GCC diagnostic ignored "-Woverloaded-virtual"
#include "antlr4-runtime.h"
#include "NomeParserBase.h"
#include "NomeLexer.h"
#include "NomeParser.h"
#pragma GCC diagnostic pop
