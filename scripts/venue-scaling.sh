#!/usr/bin/env bash
# Issue 16: bake time and peak memory of the generated venue at several
# model sizes, and the growth exponent fitted to them (least squares on
# log time and log memory against log faces).
#
#   scripts/venue-scaling.sh [BUILD_DIR] [LUMINAIRES] [SIZES...]
#   scripts/venue-scaling.sh build 2 3000 6000 12000 25000
#
# LUMINAIRES (default 2) keeps the first N of the rig: the links, which grow
# with the model, are the same for any rig; the solves grow with faces x
# luminaires. Each bake is capped at RELIGHT_VENUE_CAP seconds (default 900);
# a capped size is reported and left out of the fit. Wall times on a shared
# machine: say the load average next to them (printed). RELIGHT_VENUE_ARGS
# adds arguments to every bake (e.g. "--clusters off" for the old start from
# every pair of surfaces, "--absolute-links").
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}; shift || true
lum=${1:-2}; shift || true
sizes=("$@"); [ ${#sizes[@]} -gt 0 ] || sizes=(3000 6000 12000 25000)
cap=${RELIGHT_VENUE_CAP:-900}
tmp=${TMPDIR:-/tmp}/venue-scaling
mkdir -p "$tmp"
rows="$tmp/rows.txt"; : >"$rows"
read -r -a extra <<<"${RELIGHT_VENUE_ARGS:-}"
echo "| triangles | faces | patches | links | cluster links | form factors s | solve s | wall s | peak MB | load avg |"
echo "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"
for t in "${sizes[@]}"; do
  gen=$(python3 scripts/make-venue.py --triangles "$t" --luminaires "$lum" -o "$tmp/v$t")
  faces=$(sed -n 's/.* triangles, \([0-9]*\) faces.*/\1/p' <<<"$gen")
  tris=$(sed -n 's/^make-venue: \([0-9]*\) triangles.*/\1/p' <<<"$gen")
  load=$(cut -d' ' -f1 /proc/loadavg)
  rc=0
  /usr/bin/time -f "%e %M" -o "$tmp/time$t" timeout "$cap" \
    "$build/baker/relight-bake" "$tmp/v$t/venue.toml" -o "$tmp/v$t.rlb" --solver hierarchical "${extra[@]}" \
    >"$tmp/log$t" 2>&1 </dev/null || rc=$?
  if [ "$rc" -ne 0 ]; then
    echo "| $tris | $faces | — | — | — | — | — | > $cap (stopped, exit $rc) | — | $load |"
    continue
  fi
  read -r wall kb <"$tmp/time$t"
  summary=$(grep "^relight-bake: venue:" "$tmp/log$t")
  patches=$(sed -n 's/.*venue: \([0-9]*\) patches.*/\1/p' <<<"$summary")
  links=$(sed -n 's/.* nodes, \([0-9]*\) links.*/\1/p' <<<"$summary")
  clinks=$(sed -n 's/.* clusters with \([0-9]*\) cluster links.*/\1/p' <<<"$summary")
  ff=$(sed -n 's/.*form factors \([0-9.]*\) s.*/\1/p' <<<"$summary")
  solve=$(sed -n 's/.*solve \([0-9.]*\) s.*/\1/p' <<<"$summary")
  mb=$((kb / 1024))
  echo "| $tris | $faces | $patches | $links | ${clinks:-0} | $ff | $solve | $wall | $mb | $load |"
  echo "$faces $wall $mb $ff $links" >>"$rows"
done
python3 - "$rows" <<'PY'
import math, sys
rows = [list(map(float, l.split())) for l in open(sys.argv[1]) if l.strip()]
def fit(col):
    xs = [math.log(r[0]) for r in rows]; ys = [math.log(r[col]) for r in rows]
    n = len(xs); mx = sum(xs) / n; my = sum(ys) / n
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
if len(rows) >= 2:
    print(f"\ngrowth exponent vs faces (log-log least squares over {len(rows)} sizes): "
          f"wall {fit(1):.2f}, peak memory {fit(2):.2f}, form factors {fit(3):.2f}, links {fit(4):.2f}")
else:
    print("\nfewer than 2 sizes finished: no fit")
PY
