#!/usr/bin/env python3
"""Bytes a bake file stores per section tag (docs/bake-format.md "Table of
contents entry"): stored (on disk, zstd where that is smaller) and raw.

    scripts/bake-section-sizes.py BAKE.rlb [BAKE.rlb ...]
"""
import collections
import struct
import sys

HEADER = 28
TOC_ENTRY = 36


def sizes(path):
    data = open(path, "rb").read(1 << 20)
    count = struct.unpack_from("<I", data, 12)[0]
    if HEADER + count * TOC_ENTRY > len(data):
        data = open(path, "rb").read(HEADER + count * TOC_ENTRY)
    out = collections.OrderedDict()
    for i in range(count):
        tag, _, _, stored, raw, _ = struct.unpack_from("<IIQQQI", data, HEADER + i * TOC_ENTRY)
        name = struct.pack("<I", tag).decode("ascii", "replace")
        s, r, n = out.get(name, (0, 0, 0))
        out[name] = (s + stored, r + raw, n + 1)
    return out


def main(paths):
    for path in paths:
        print(path)
        for name, (stored, raw, n) in sizes(path).items():
            print(f"  {name} x{n}: stored {stored / 2**20:.2f} MB, raw {raw / 2**20:.2f} MB")


if __name__ == "__main__":
    main(sys.argv[1:])
