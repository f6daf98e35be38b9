#!/bin/sh
# Fails if the given object files or archives contain floating-point
# instructions. The instruction set is read from objdump's "file format"
# line; OBJDUMP names the objdump to use (aarch64-linux-gnu-objdump for a
# cross build; default objdump).
#   x86-64: x87, or SSE/AVX scalar/packed float arithmetic, compares and
#     conversions. Plain 128/256-bit moves and bitwise ops (movaps, xorps)
#     are data movement, not floating point, and are allowed.
#   aarch64: every A64 mnemonic starting with f is a floating-point one
#     (fadd, fmul, fmadd, fcvt*, fcmp, fcsel, frint*, fmov to/from s/d/v
#     registers, and their vector forms), plus scvtf/ucvtf (integer to float).
#     Integer NEON (add v0.4s, ...) is not floating point.
set -eu
OBJDUMP=${OBJDUMP:-objdump}
X86_FLOAT='^\s*(v?(add|sub|mul|div|sqrt|min|max|rcp|rsqrt|cmp|round|fmadd|fmsub|fnmadd|fnmsub|hadd|hsub|dp)[a-z0-9]*(ss|sd|ps|pd)|v?u?comis[sd]|v?cvt[a-z0-9]*|f(ld|st|add|sub|mul|div|ild|ist|com|ucom|sqrt|sin|cos|xch|chs|abs|prem|scale|rndint)[a-z]*)\b'
A64_FLOAT='^\s*(f[a-z0-9]+|[su]cvtf)(\s|$)'
status=0
for f in "$@"; do
  listing=$("$OBJDUMP" -d --no-show-raw-insn "$f")
  case $(printf '%s\n' "$listing" | grep -m1 'file format' || true) in
    *aarch64*) regex=$A64_FLOAT; arch=aarch64 ;;
    *x86-64*) regex=$X86_FLOAT; arch=x86-64 ;;
    *) echo "no_float_check: unknown instruction set in $f (OBJDUMP=$OBJDUMP)"; exit 1 ;;
  esac
  # Fields: "addr:", mnemonic (x86-64: with operands), operands (aarch64).
  hits=$(printf '%s\n' "$listing" | awk -F'\t' 'NF >= 2 { print $2 "\t" $3 }' | grep -E "$regex" || true)
  if [ -n "$hits" ]; then
    echo "$arch floating-point instructions in $f:"
    echo "$hits" | sort | uniq -c | sort -rn | head -20
    status=1
  fi
done
[ $status -eq 0 ] && echo "no floating-point instructions ($arch) in: $*"
exit $status
