#!/usr/bin/env python3
"""The rate-error curve of the basis compression (docs/performance.md,
"Compressed bases") from relight-bake's --compress-curve CSV: for each
cluster length and component count r, the vertex bases of all luminaires
together (bytes summed, the ratio against the same values as float32) and
the error (largest over luminaires, mean of their means), unquantised, as a
fraction of each luminaire's own peak at the baker's random looks.

    scripts/plot-compression-curve.py CURVE.csv VERTICES OUT.png

Needs python3-matplotlib (docs only, not CI).
"""
import collections
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(path, vertices, out):
    rows = [r for r in csv.DictReader(open(path)) if r["set"] == "0"]
    lums = {r["luminaire"] for r in rows}
    # Each luminaire's term count T from a candidate with r = 0, whose bytes
    # are 4 (C + 1) + 6 T C + 24 T (compress_basis.cc CompressedMemory).
    terms = {}
    for r in rows:
        if r["components"] == "0":
            c = int(r["clusters"])
            terms[r["luminaire"]] = (int(r["bytes"]) - 4 * (c + 1)) // (6 * c + 24)
    groups = collections.defaultdict(list)
    for r in rows:
        groups[(int(r["cluster_size"]), int(r["components"]))].append(r)
    float32 = sum(4 * 3 * t * vertices for t in terms.values())
    fig, (ax_max, ax_mean) = plt.subplots(1, 2, figsize=(11, 4.2))
    for size in sorted({k[0] for k in groups}):
        pts = []
        for (s, r), rs in sorted(groups.items()):
            if s != size or len(rs) != len(lums):
                continue
            ratio = float32 / sum(int(x["bytes"]) for x in rs)
            worst = max(float(x["max_error"]) for x in rs)
            mean = sum(float(x["mean_error"]) for x in rs) / len(rs)
            pts.append((ratio, 100 * worst, 100 * mean, r))
        if not pts:
            continue
        label = f"clusters of {size} vertices"
        ax_max.plot([p[0] for p in pts], [p[1] for p in pts], marker=".", label=label)
        ax_mean.plot([p[0] for p in pts], [p[2] for p in pts], marker=".", label=label)
        for p in pts:
            if p[3] in (4, 8, 16, 32):
                ax_max.annotate(f"r={p[3]}", (p[0], p[1]), fontsize=7)
    for ax, what, bar in ((ax_max, "max", 1.0), (ax_mean, "mean", 0.1)):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.axvline(16, color="grey", linestyle="--", linewidth=0.8)
        ax.axhline(bar, color="grey", linestyle="--", linewidth=0.8)
        ax.set_xlabel("size: float32 / compressed (vertex bases, all luminaires)")
        ax.set_ylabel(f"{what} error, % of each luminaire's own peak")
        ax.grid(True, which="both", linewidth=0.3)
    ax_max.legend(fontsize=7)
    fig.suptitle(f"Clustered PCA of the stage's vertex bases ({len(lums)} luminaires, {vertices} vertices, "
                 f"{sum(terms.values())} terms)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3])
