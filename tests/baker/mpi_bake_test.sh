#!/usr/bin/env bash
# Issue 16: a bake spread over MPI ranks is the same file, byte for byte, as
# the one-process bake: relight-bake without mpirun, then mpirun -np 1, 2 and
# 4 (oversubscribed on 2 cores) on the living room (3 luminaires of 36, 81
# and 36 SH terms, so 2 ranks split them 81 / 72 and 4 leave one idle),
# hierarchical so the stored links travel too. Exits 77 (skipped) without MPI.
# Usage: mpi_bake_test.sh BUILD_DIR SOURCE_DIR MPI_BUILT MPIEXEC
set -euo pipefail
build=$1 src=$2 mpi_built=$3 mpiexec=${4:-}
if [ "$mpi_built" != "ON" ] || [ -z "$mpiexec" ] || ! [ -x "$mpiexec" ]; then
  echo "mpi_bake_test: SKIPPED: relight was configured without MPI (install libopenmpi-dev" \
       "openmpi-bin, scripts/setup.sh does, and re-run cmake)"
  exit 77
fi
# CI runs as root; Open MPI refuses root without these.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Only this machine, over shared memory: nothing leaves it.
export OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bake=("$build/baker/relight-bake" "$src/fixtures/living_room.toml" --patch-size 0.4
      --solver hierarchical -q)

"${bake[@]}" -o "$tmp/plain.rlb"
want=$(sha256sum <"$tmp/plain.rlb" | cut -d' ' -f1)
for n in 1 2 4; do
  "$mpiexec" -np "$n" --oversubscribe "${bake[@]}" -o "$tmp/np$n.rlb"
  got=$(sha256sum <"$tmp/np$n.rlb" | cut -d' ' -f1)
  if [ "$got" != "$want" ]; then
    echo "mpi_bake_test: -np $n wrote $got, one process $want"
    cmp "$tmp/plain.rlb" "$tmp/np$n.rlb" | head -1 || true
    exit 1
  fi
  echo "mpi_bake_test: -np $n: $got (same as one process)"
done
# The clustered refinement too: every rank walks the clusters alike and
# shares only the surface pairs it hands on.
"${bake[@]}" --clusters on -o "$tmp/cplain.rlb"
want=$(sha256sum <"$tmp/cplain.rlb" | cut -d' ' -f1)
"$mpiexec" -np 2 --oversubscribe "${bake[@]}" --clusters on -o "$tmp/cnp2.rlb"
got=$(sha256sum <"$tmp/cnp2.rlb" | cut -d' ' -f1)
if [ "$got" != "$want" ]; then
  echo "mpi_bake_test: --clusters on -np 2 wrote $got, one process $want"
  exit 1
fi
echo "mpi_bake_test: --clusters on -np 2: $got (same as one process)"
# Only rank 0 writes: no part files left behind.
if ls "$tmp" | grep -v '^c\?\(plain\|np[124]\)\.rlb$'; then echo "stray files"; exit 1; fi
echo "mpi_bake_test: ok"
