# Shared by the command-line tests (sourced; not a test itself: tests/cli/*.sh only are tests).
# Needs $bin (the rockdem binary) and sets fail=1 on a mismatch.
# expect NAME CODE ARGS... -- SUBSTRINGS...: runs `$bin ARGS...`, wants exit CODE and every
# substring in its output (standard output and error together).
expect() {
  local name=$1 want_code=$2
  shift 2
  local args=()
  while [ "$1" != "--" ]; do args+=("$1"); shift; done
  shift
  local out code
  out=$("$bin" "${args[@]}" 2>&1)
  code=$?
  if [ "$code" -ne "$want_code" ]; then
    echo "FAIL $name: exit $code, wanted $want_code: $out"
    fail=1
    return
  fi
  for want in "$@"; do
    if ! grep -qF -- "$want" <<<"$out"; then
      echo "FAIL $name: output lacks '$want': $out"
      fail=1
    fi
  done
  echo "ok   $name: $(head -c 300 <<<"$out" | tr '\n' ' ')"
}
