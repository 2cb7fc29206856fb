#!/usr/bin/env python3
# Seeds for fuzz_defocus (its layout: fuzz_defocus.cpp): small plates and
# deep images of a wall, a receding floor and a block in front, under a thin
# lens or a blur map, with holes, alpha, bokeh, counted slices, the ADI
# solver and no depth cleanup. Usage: defocus_seeds.py DIR
import os
import sys

THIN_LENS, DEEP, BOKEH, ALPHA, COUNT, NO_CLEANUP, ADI = 64, 1, 2, 4, 8, 32, 128
WALL, BLOCK = 120, 40  # depth bytes: 0.5 * 1.03^b m (17 m, 1.6 m)


def block(x, y):
    return 3 <= x < 7 and 2 <= y < 6


def plate(w, h, flags, strength, param, holes=False):
    out = bytearray([w - 1, h - 1, flags, strength, param])
    for y in range(h):
        for x in range(w):
            z = BLOCK if block(x, y) else (60 + (h - y) * 6 if y >= h // 2 else WALL)
            if holes and (x + y) % 7 == 0:
                z = 240 if x % 2 else 242  # depth 0, NaN
            out.append(z)
            if flags & ALPHA:
                out.append(120 if (x, y) == (0, 0) else 249)
            base = (x * 13 + y * 7) % 200
            out += bytes([base, base * 3 % 250, 240 if z == BLOCK else 30])
    if not flags & THIN_LENS:  # the blur map: the block blurred most
        out += bytes(255 if block(x, y) else 20 for y in range(h) for x in range(w))
    return bytes(out)


def deep(w, h, flags, strength, param):
    out = bytearray([w - 1, h - 1, flags, strength, param])
    counts = [2 if x == 4 else (0 if (x, y) == (0, 0) else 1) for y in range(h) for x in range(w)]
    out += bytes(counts)
    for i, n in enumerate(counts):
        for s in range(n):
            front = s == 0 and i % w == 4
            out += bytes([BLOCK if front else WALL, 125 if front else 249, 100, 50, 20])
    if not flags & THIN_LENS:
        out += bytes(200 if x < 5 else 10 for y in range(h) for x in range(w))
    return bytes(out)


seeds = {
    "plate_thin_lens": plate(12, 10, THIN_LENS, 3, 60),
    "plate_map": plate(12, 10, 0, 200, 0),
    "plate_map_bokeh_alpha": plate(10, 8, BOKEH | ALPHA, 160, 0),
    "plate_holes_count": plate(12, 10, THIN_LENS | COUNT, 3, 3, holes=True),
    "plate_adi_no_cleanup": plate(9, 9, THIN_LENS | ADI | NO_CLEANUP, 3, 70),
    "deep_map": deep(8, 6, DEEP, 220, 0),
    "deep_thin_lens_bokeh": deep(8, 6, DEEP | BOKEH | THIN_LENS, 3, 55),
}
os.makedirs(sys.argv[1], exist_ok=True)
for name, data in seeds.items():
    with open(os.path.join(sys.argv[1], name), "wb") as f:
        f.write(data)
