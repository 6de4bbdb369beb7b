# vscode.cmake: CTest tests for the VS Code extension in editors/vscode (included from
# tests/vscode/CMakeLists.txt). Registered only when `node` and `npm` are found, so the core
# build never needs Node.js. `vscode_setup` (fixture) runs `npm ci` when node_modules is
# missing or stale, then compiles; the grammar, end-to-end and packaging tests need it.
find_program(NOMEC_NODE node)
find_program(NOMEC_NPM npm)
if(NOT NOMEC_NODE OR NOT NOMEC_NPM)
  message(STATUS "editors/vscode: node or npm not found; the vscode_* tests are not registered")
  return()
endif()

set(_vscode_dir "${PROJECT_SOURCE_DIR}/editors/vscode")
find_package(Python3 REQUIRED COMPONENTS Interpreter)

add_test(NAME vscode_setup COMMAND bash "${_vscode_dir}/scripts/ci.sh" setup)
add_test(NAME vscode_grammar COMMAND "${NOMEC_NODE}" "${_vscode_dir}/out/test/grammar.test.js")
add_test(NAME vscode_e2e COMMAND "${NOMEC_NODE}" "${_vscode_dir}/out/test/e2e.test.js" "$<TARGET_FILE:nomec>")
add_test(NAME vscode_package COMMAND bash "${_vscode_dir}/scripts/ci.sh" package)

set_tests_properties(vscode_setup PROPERTIES FIXTURES_SETUP vscode_node_modules TIMEOUT 900)
set_tests_properties(vscode_grammar vscode_e2e vscode_package PROPERTIES
  FIXTURES_REQUIRED vscode_node_modules TIMEOUT 300)
if(IS_DIRECTORY "${NOMEC_CORPUS_DIR}")
  # The grammar's file-wide checks also run over every corpus file, read in place.
  set_tests_properties(vscode_grammar PROPERTIES ENVIRONMENT "NOME_GRAMMAR_EXTRA_DIRS=${NOMEC_CORPUS_DIR}")
endif()
# `npm run package` recompiles out/, which the other tests read: never at the same time.
set_tests_properties(vscode_setup vscode_grammar vscode_e2e vscode_package PROPERTIES
  RESOURCE_LOCK vscode_out LABELS vscode)
