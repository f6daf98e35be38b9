#!/bin/sh
# Fails if the given object files or archives contain x86-64 floating-point
# instructions (x87, or SSE/AVX scalar/packed float arithmetic, compares and
# conversions). Plain 128/256-bit moves and bitwise ops (movaps, xorps) are
# data movement, not floating point, and are allowed.
set -eu
status=0
for f in "$@"; do
  hits=$(objdump -d --no-show-raw-insn "$f" | awk -F'\t' 'NF >= 2 { print $2 }' |
    grep -E '^\s*(v?(add|sub|mul|div|sqrt|min|max|rcp|rsqrt|cmp|round|fmadd|fmsub|fnmadd|fnmsub|hadd|hsub|dp)[a-z0-9]*(ss|sd|ps|pd)|v?u?comis[sd]|v?cvt[a-z0-9]*|f(ld|st|add|sub|mul|div|ild|ist|com|ucom|sqrt|sin|cos|xch|chs|abs|prem|scale|rndint)[a-z]*)\b' || true)
  if [ -n "$hits" ]; then
    echo "floating-point instructions in $f:"
    echo "$hits" | sort | uniq -c | head -20
    status=1
  fi
done
[ $status -eq 0 ] && echo "no floating-point instructions in: $*"
exit $status
