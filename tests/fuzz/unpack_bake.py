#!/usr/bin/env python3
"""Rewrites a bake file with every section stored uncompressed (flags 0),
crcs recomputed: the seeds of bake_sections_fuzz, whose mutations should
land in the section decoders' bytes rather than in zstd frames.
docs/bake-format.md "File layout" is the format.

    tests/fuzz/unpack_bake.py IN.rlb OUT.rlb
"""
import ctypes
import struct
import sys
import zlib

HEADER = 28
TOC_ENTRY = 36
ZSTD_FLAG = 1


def main(src, dst):
    data = open(src, "rb").read()
    zstd = ctypes.CDLL("libzstd.so.1")
    zstd.ZSTD_decompress.restype = ctypes.c_size_t
    zstd.ZSTD_isError.restype = ctypes.c_uint
    count = struct.unpack_from("<I", data, 12)[0]
    sections = []
    for i in range(count):
        tag, flags, offset, stored, raw, _ = struct.unpack_from("<IIQQQI", data, HEADER + i * TOC_ENTRY)
        payload = data[offset:offset + stored]
        if flags & ZSTD_FLAG:
            out = ctypes.create_string_buffer(raw)
            n = zstd.ZSTD_decompress(out, raw, payload, len(payload))
            if zstd.ZSTD_isError(n) or n != raw:
                sys.exit(f"{src}: section {i} does not decompress")
            payload = out.raw[:raw]
        sections.append((tag, payload))
    offset = HEADER + count * TOC_ENTRY
    toc, body = b"", b""
    for tag, payload in sections:
        toc += struct.pack("<IIQQQI", tag, 0, offset, len(payload), len(payload), zlib.crc32(payload))
        offset += len(payload)
        body += payload
    header = bytearray(data[:HEADER])
    struct.pack_into("<Q", header, 16, offset)  # file size
    crc = zlib.crc32(toc, zlib.crc32(bytes(header[:24])))
    struct.pack_into("<I", header, 24, crc)
    open(dst, "wb").write(bytes(header) + toc + body)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
