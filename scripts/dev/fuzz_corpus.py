#!/usr/bin/env python3
"""Packs a fuzz target's corpus folder into one file, or unpacks it.

fuzz_corpus.py pack DIR FILE     every file in DIR (sorted by name) into FILE
fuzz_corpus.py unpack FILE DIR   FILE's inputs into DIR, one file each (named by index)

The packed form is what test/fuzz_corpus/<target>.corpus holds: a sequence of
records, each a 4-byte little-endian length followed by that many bytes. test_fuzz_inputs replays it.
"""
import os
import struct
import sys


def pack(folder, path):
    names = sorted(os.listdir(folder))
    with open(path, "wb") as out:
        for name in names:
            with open(os.path.join(folder, name), "rb") as f:
                data = f.read()
            out.write(struct.pack("<I", len(data)))
            out.write(data)
    print(f"{path}: {len(names)} inputs")


def unpack(path, folder):
    os.makedirs(folder, exist_ok=True)
    with open(path, "rb") as f:
        blob = f.read()
    at, index = 0, 0
    while at < len(blob):
        if at + 4 > len(blob):
            sys.exit(f"{path}: truncated record header at byte {at}")
        (size,) = struct.unpack_from("<I", blob, at)
        at += 4
        if at + size > len(blob):
            sys.exit(f"{path}: record {index} runs past the end")
        with open(os.path.join(folder, f"kept_{index:05d}"), "wb") as out:
            out.write(blob[at:at + size])
        at += size
        index += 1
    print(f"{folder}: {index} inputs")


if __name__ == "__main__":
    if len(sys.argv) != 4 or sys.argv[1] not in ("pack", "unpack"):
        sys.exit(__doc__)
    (pack if sys.argv[1] == "pack" else unpack)(sys.argv[2], sys.argv[3])
