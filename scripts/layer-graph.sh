#!/usr/bin/env bash
# Fails if a layer links one it must not (docs/architecture.md), from
# CMake's --graphviz output of a scratch configure; then, unless --check is
# given, draws relight's own libraries and their links into
# docs/figures/layers.svg (needs graphviz's dot).
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cat > "$out/CMakeGraphVizOptions.cmake" <<'OPT'
set(GRAPHVIZ_EXTERNAL_LIBS FALSE)
set(GRAPHVIZ_EXECUTABLES FALSE)
set(GRAPHVIZ_GENERATE_PER_TARGET FALSE)
set(GRAPHVIZ_GENERATE_DEPENDERS FALSE)
set(GRAPHVIZ_IGNORE_TARGETS "test|bench|relight_test_image|_simd|_format")
OPT
cmake -S . -B "$out" -DRELIGHT_BUILD_TESTS=OFF -DRELIGHT_BUILD_BENCHMARKS=OFF --graphviz="$out/relight.dot" > /dev/null
# Reachability check: hal must not reach bake, engine or render; engine not hal.
python3 - "$out/relight.dot" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
names = dict(re.findall(r'"(node\d+)" \[ label = "([^"]+)"', text))
edges = {}
for a, b in re.findall(r'"(node\d+)" -> "(node\d+)"', text):
    edges.setdefault(names[a], set()).add(names[b])
def reach(t, seen=None):
    seen = set() if seen is None else seen
    for n in edges.get(t, ()):
        if n not in seen:
            seen.add(n); reach(n, seen)
    return seen
bad = []
for t in names.values():
    r = reach(t)
    if t.startswith('relight_hal') and r & {'relight_bake', 'relight_engine', 'relight_render'}:
        bad.append(f'{t} reaches {sorted(r & {"relight_bake", "relight_engine", "relight_render"})}')
    if t in ('relight_base',) and r:
        bad.append(f'{t} links {sorted(r)}')
    if t in ('relight_bake', 'relight_engine', 'relight_render') and any(x.startswith('relight_hal') for x in r):
        bad.append(f'{t} reaches hal')
    if t == 'relight_baker' and r & {'relight_engine', 'relight_render'}:
        bad.append(f'relight_baker reaches {sorted(r & {"relight_engine", "relight_render"})}')
if bad:
    print('layer violations:\n  ' + '\n  '.join(bad)); sys.exit(1)
print(f'layers: {len(names)} libraries, no link against the layering')
PY
# And in the sources: no file under hal/ includes a bake, engine or render header.
if grep -rlE '#include "relight/(bake|engine|render|control)/' hal/; then
  echo "hal/ includes headers of layers above it (files listed above)"; exit 1
fi
[ "${1:-}" = "--check" ] && exit 0
dot -Tsvg "$out/relight.dot" -o docs/figures/layers.svg
echo "wrote docs/figures/layers.svg"
