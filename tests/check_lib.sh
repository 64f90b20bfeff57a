# Shared by the shell test scripts (source it): PASS/FAIL lines and their counts.
#   ok NAME             a passed check
#   nok NAME [LINE...]  a failed check, with lines of detail
#   finish SCRIPT       prints "SCRIPT: N passed, M failed"; the exit status is 1 on any failure
#   run_cli ARGS...     runs $APICLAB in $TMP/cwd within CLI_TIMEOUT s (default 120); sets RC,
#                       OUT and ERR (files)
pass=0
fail=0
ok() {
  pass=$((pass + 1))
  echo "PASS: $1"
}
nok() {
  fail=$((fail + 1))
  echo "FAIL: $1"
  shift
  for line in "$@"; do echo "      $line"; done
}
finish() {
  echo "$1: $pass passed, $fail failed"
  [ "$fail" -eq 0 ]
}
run_cli() {
  OUT="$TMP/stdout" ERR="$TMP/stderr"
  (cd "$TMP/cwd" && exec timeout "${CLI_TIMEOUT:-120}" "$APICLAB" "$@") >"$OUT" 2>"$ERR"
  RC=$?
}
