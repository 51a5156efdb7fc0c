#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Build docs/spd-compare.png: ggrt (left) beside POV-Ray 3.7 (right) for the
seven SPD scenes, from the thumbnails in docs/spd/ that scripts/spd-thumbs.sh
renders. Pure Python (zlib), no imaging library needed."""
import struct
import sys
import zlib

NAMES = ["balls-s4", "gears", "rings", "tetra", "mount", "tree", "teapot-s12"]


def readpng(path):
    data = open(path, "rb").read()
    i, idat, w, h, ctype = 8, b"", 0, 0, 2
    while i < len(data):
        n = struct.unpack(">I", data[i:i + 4])[0]
        kind, body = data[i + 4:i + 8], data[i + 8:i + 8 + n]
        i += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", body[:10])
            if depth != 8 or ctype not in (2, 6):
                sys.exit("%s: only 8-bit RGB(A) PNGs" % path)
        elif kind == b"IDAT":
            idat += body
    raw, bpp = zlib.decompress(idat), 3 if ctype == 2 else 4
    stride, rows, prev, k = w * bpp, [], bytearray(w * bpp), 0
    for _ in range(h):
        f, line = raw[k], bytearray(raw[k + 1:k + 1 + stride])
        k += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b, c = prev[x], prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(v for j, v in enumerate(line) if bpp == 3 or j % 4 != 3))
        prev = line
    return w, h, rows


def main():
    rows = []
    for name in NAMES:
        w, h, a = readpng("docs/spd/ggrt-%s.png" % name)
        _, _, b = readpng("docs/spd/pov-%s.png" % name)
        rows += [a[y] + bytes([255] * 12) + b[y] for y in range(h)]
        rows.append(bytes([255] * len(rows[-1])))
    width, height = len(rows[0]) // 3, len(rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(
            ">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(b"".join(b"\x00" + r for r in rows), 9)) + chunk(b"IEND", b"")
    open("docs/spd-compare.png", "wb").write(png)
    print("wrote docs/spd-compare.png (%dx%d)" % (width, height))


main()
