#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the hostile image files of issue 16 into a folder.

    python3 tests/data/hostile.py DIR          the small files (under 4 KB):
        big.png      a 16384 x 16384 RGB PNG header, 64 rows of data
        big.exr      a 16384 x 16384 OpenEXR header and nothing else
        lie.png      a 4096 x 4096 PNG whose IDAT length field says 2 GB
        tex1m.png    296 x 296 RGB: 1,051,392 bytes once decoded (12 per pixel)
        short.exr    a 4 x 2 uncompressed float OpenEXR whose second
                     scanline chunk holds 20 of its 48 bytes
        short2.exr   the same with the chunk's size field saying 48 and the
                     file ending after 20 bytes of it
        plain.exr    the same file whole (valid)
    python3 tests/data/hostile.py DIR --full   also, each under 100 KB:
        full_a.png, full_b.png   4096 x 4096 RGB PNGs with every row present
                                 (192 MiB decoded each: the largest image the
                                 limits allow)

tests/data/hostile/ and tests/fuzz/corpus/image/ hold the small files as
this script writes them; tests/cli/t_limits.sh writes the full ones.
"""
import os
import struct
import sys
import zlib


def chunk(kind, data, length=None):
    n = len(data) if length is None else length
    return struct.pack('>I', n) + kind + data + struct.pack('>I', zlib.crc32(kind + data))


def png(w, h, rows=None, lie=None, full=False, shade=0):
    ihdr = struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)
    comp = zlib.compressobj(9)
    if rows is not None:
        raw = comp.compress(rows)
    else:
        row = b'\0' + bytes([shade]) * (3 * w)
        raw = b''.join(comp.compress(row) for _ in range(h if full else min(h, 64)))
    raw += comp.flush()
    return (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', ihdr) + chunk(b'IDAT', raw, lie) +
            chunk(b'IEND', b''))


def attr(name, kind, value):
    return name + b'\0' + kind + b'\0' + struct.pack('<i', len(value)) + value


def exr_header(w, h, channels=(b'B', b'G', b'R')):
    chl = b''.join(c + b'\0' + struct.pack('<iB3xii', 2, 0, 1, 1) for c in channels) + b'\0'
    box = struct.pack('<4i', 0, 0, w - 1, h - 1)
    return (b'\x76\x2f\x31\x01' + struct.pack('<i', 2) + attr(b'channels', b'chlist', chl) +
            attr(b'compression', b'compression', b'\0') + attr(b'dataWindow', b'box2i', box) +
            attr(b'displayWindow', b'box2i', box) + attr(b'lineOrder', b'lineOrder', b'\0') +
            attr(b'pixelAspectRatio', b'float', struct.pack('<f', 1.0)) +
            attr(b'screenWindowCenter', b'v2f', struct.pack('<2f', 0, 0)) +
            attr(b'screenWindowWidth', b'float', struct.pack('<f', 1.0)) + b'\0')


def short_exr(lie, whole=False):
    """4 x 2 float B, G, R, uncompressed: one scanline per chunk."""
    w, h = 4, 2
    head = exr_header(w, h)
    line = struct.pack('<12f', *([0.25] * 12))  # 3 channels x 4 pixels
    table = len(head) + 8 * h
    c0 = struct.pack('<ii', 0, len(line)) + line
    part = line if whole else line[:20]
    c1 = struct.pack('<ii', 1, len(line) if lie else len(part)) + part
    offsets = struct.pack('<2Q', table, table + len(c0))
    return head + offsets + c0 + c1


def main():
    d = sys.argv[1]
    os.makedirs(d, exist_ok=True)
    w = 296
    tex = b''.join(b'\0' + bytes((x * 7 + y) & 255 for x in range(3 * w)) for y in range(w))
    files = {
        'big.png': png(16384, 16384),
        'big.exr': exr_header(16384, 16384) + b'\0' * 16,
        'lie.png': png(4096, 4096, lie=0x7ffffff0),
        'tex1m.png': png(w, w, rows=tex),
        'short.exr': short_exr(False),
        'short2.exr': short_exr(True),
        'plain.exr': short_exr(False, whole=True),
    }
    if '--full' in sys.argv[2:]:
        files['full_a.png'] = png(4096, 4096, full=True, shade=64)
        files['full_b.png'] = png(4096, 4096, full=True, shade=128)
    for name, data in files.items():
        with open(os.path.join(d, name), 'wb') as f:
            f.write(data)


if __name__ == '__main__':
    main()
