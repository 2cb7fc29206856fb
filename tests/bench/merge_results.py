#!/usr/bin/env python3
"""Merge a partial benchmark run into the full one (tests/bench/run --merge).

    merge_results.py FULL.csv PART.csv

Every row of PART.csv replaces the row of FULL.csv with the same scene,
size, field, method and setting, or is added when FULL.csv has none (a
second size, say). FULL.csv is rewritten in place; the order of its rows is
kept, added rows go after the last row of their scene and size (or at the
end). The last line printed says what was merged (for the tables' header).
"""
import csv
import sys

KEY = ("scene", "width", "height", "field", "method", "setting")


def read(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        return reader.fieldnames, list(reader)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    full_path, part_path = sys.argv[1], sys.argv[2]
    fields, full = read(full_path)
    part_fields, part = read(part_path)
    if part_fields != fields:
        sys.exit(f"{part_path}: its columns differ from {full_path}'s")
    key = lambda r: tuple(r[k] for k in KEY)
    index = {key(r): i for i, r in enumerate(full)}
    replaced, added = 0, []
    for r in part:
        i = index.get(key(r))
        if i is None:
            added.append(r)
        else:
            full[i] = r
            replaced += 1
    for r in added:
        # After the last row of the same scene and size, else at the end.
        same = [i for i, f in enumerate(full) if (f["scene"], f["width"], f["height"]) == (r["scene"], r["width"], r["height"])]
        full.insert(same[-1] + 1 if same else len(full), r)
    with open(full_path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, lineterminator="\n")
        w.writeheader()
        w.writerows(full)
    print(f"{full_path}: {replaced} rows replaced, {len(added)} added from {part_path}", file=sys.stderr)
    sizes = sorted({(int(r["width"]), int(r["height"])) for r in part})
    families = sorted({r["method"].split(" ")[0] for r in part})
    print(", ".join(f"{w}x{h}" for w, h in sizes) + " rows of " + ", ".join(families))


if __name__ == "__main__":
    main()
