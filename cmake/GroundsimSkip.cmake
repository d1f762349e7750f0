# groundsim_skipped_test(NAME REASON LABELS...): a test that only prints
# "SKIP: REASON" and exits 77, so that a test whose tool is missing at
# configure time (node, Emscripten, pybind11) is listed as skipped with its
# reason instead of vanishing from the count (scripts/test.sh lists skips).
function(groundsim_skipped_test name reason)
  add_test(NAME ${name} COMMAND sh -c "echo 'SKIP: ${reason}'; exit 77")
  set_tests_properties(${name} PROPERTIES SKIP_RETURN_CODE 77 LABELS "${ARGN}")
endfunction()
