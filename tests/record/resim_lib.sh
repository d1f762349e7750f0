# Shared by the re-simulation tests (resim_record.sh, race_resim.sh,
# refine_resim.sh); sourced once build, gs, dir and fail() are set.

# start_server [ARGS...]: a server on the namespace's bus, its output in
# $dir/server.out, once a client's `list` is answered (or 60 s have passed:
# a ceiling for a hung start, not a verdict)
start_server() {
  "$build/server/lcm/groundsim-server" "$@" > "$dir/server.out" 2>&1 &
  for _ in $(seq 600); do "$gs" list > /dev/null 2>&1 && break; sleep 0.1; done
}

# expect_identical FILE SESSION: `groundsim replay --resimulate` of the
# session reaches every recorded state bit for bit (its output printed, and
# kept in $dir/same.txt for further checks)
expect_identical() {
  "$gs" replay --resimulate "$1" --session "$2" > "$dir/same.txt" 2>&1 ||
    { cat "$dir/same.txt"; fail "session $2 did not re-simulate to the same states"; }
  cat "$dir/same.txt"
  grep -q "^identical: session $2" "$dir/same.txt" || fail "no identical line"
  grep -q "^compared bit for bit" "$dir/same.txt" || fail "not bit for bit"
}
