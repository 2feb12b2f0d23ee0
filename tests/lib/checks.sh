# The shell tests' checks, sourced by each script after it sets ROOT:
#   . "$ROOT/tests/lib/checks.sh"
#   check "what holds" '<shell expression>'   evaluates the expression; prints "ok: ..." or
#                                             "FAIL: ..." and counts it
#   checks_done [note]                        prints the tally (and the note); its status, the
#                                             script's last command, is 0 only if none failed
fails=0 checks=0
check() {
  checks=$((checks + 1))
  if eval "$2"; then echo "ok: $1"; else echo "FAIL: $1"; fails=$((fails + 1)); fi
}
checks_done() {
  echo "$((checks - fails)) passed, $fails failed${1:+ $1}"
  [ "$fails" -eq 0 ]
}
