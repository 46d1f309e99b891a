#!/usr/bin/env python3
"""Degenerate inputs for the reliability suite (tests/cli/reliability_*.sh), generated on the fly
with fixed seeds (never committed). Standard library only.

  make_degenerate.py ply OUT.ply N [--coincident] [--zero-features] [--quat-scale S] [--no-opacity] [--seed S]
      INRIA-layout binary PLY: x y z, scale_0..2, rot_0..3, opacity, f_dc_0..2, semantic_0..7.
  make_degenerate.py mask OUT.npy N FIRST COUNT     bool mask: Gaussians FIRST..FIRST+COUNT-1 removed
  make_degenerate.py cameras OUT.json NAME...       INRIA cameras.json, one orbit camera per NAME
                                                    (NAME may hold '/', NUL as \\0, or repeat)
  make_degenerate.py png OUT.png W H                8-bit grey PNG of zeros (small file, huge decode)
"""
import array
import json
import math
import random
import struct
import sys
import zlib


def write_ply(path, n, coincident=False, zero_features=False, quat_scale=1.0, opacity=True, seed=1):
    rng = random.Random(seed)
    props = ["x", "y", "z", "scale_0", "scale_1", "scale_2", "rot_0", "rot_1", "rot_2", "rot_3"]
    if opacity:
        props.append("opacity")
    props += ["f_dc_0", "f_dc_1", "f_dc_2"] + ["semantic_%d" % d for d in range(8)]
    data = array.array("f")
    for i in range(n):
        if coincident:
            xyz = (0.25, -0.5, 1.0)
        else:
            xyz = (rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1))
        q = [rng.gauss(0, 1) for _ in range(4)]
        qn = math.sqrt(sum(v * v for v in q)) or 1.0
        q = [v / qn * quat_scale for v in q]
        obj = 1.0 if i < n // 10 else 0.0  # the first tenth is "the object"
        feat = [0.0] * 8 if zero_features else [obj, 1.0 - obj] + [rng.uniform(-0.1, 0.1) for _ in range(6)]
        row = list(xyz) + [math.log(0.02)] * 3 + q
        if opacity:
            row.append(2.0)
        row += [rng.uniform(-1, 1) for _ in range(3)] + feat
        data.extend(row)
    header = "ply\nformat binary_little_endian 1.0\nelement vertex %d\n" % n
    header += "".join("property float %s\n" % p for p in props) + "end_header\n"
    with open(path, "wb") as f:
        f.write(header.encode())
        if sys.byteorder != "little":
            data.byteswap()
        f.write(data.tobytes())


def write_mask(path, n, first, count):
    body = bytes(1 if first <= i < first + count else 0 for i in range(n))
    header = "{'descr': '|b1', 'fortran_order': False, 'shape': (%d,), }" % n
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    with open(path, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode() + body)


def write_cameras(path, names):
    cams = []
    for i, name in enumerate(names):
        a = 2 * math.pi * i / max(1, len(names))
        pos = [3 * math.cos(a), 0.0, 3 * math.sin(a)]
        fwd = [-p / 3 for p in pos]  # looks at the origin; y down
        right = [fwd[2], 0.0, -fwd[0]]
        down = [fwd[1] * right[2] - fwd[2] * right[1], fwd[2] * right[0] - fwd[0] * right[2],
                fwd[0] * right[1] - fwd[1] * right[0]]
        rot = [[right[r], down[r], fwd[r]] for r in range(3)]  # camera-to-world columns
        cams.append({"id": i, "img_name": name.replace("\\0", "\0"), "width": 32, "height": 24,
                     "position": pos, "rotation": rot, "fx": 30.0, "fy": 30.0})
    with open(path, "w") as f:
        json.dump(cams, f)


def write_png(path, w, h):
    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)
    comp = zlib.compressobj(9)
    row = b"\x00" * (w + 1)  # filter byte + zeros
    idat = b"".join(comp.compress(row) for _ in range(h)) + comp.flush()
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0)))
        f.write(chunk(b"IDAT", idat) + chunk(b"IEND", b""))


def main(argv):
    kind, out = argv[1], argv[2]
    if kind == "ply":
        n = int(argv[3])
        opts = argv[4:]
        def value(flag, default):
            return float(opts[opts.index(flag) + 1]) if flag in opts else default
        write_ply(out, n, "--coincident" in opts, "--zero-features" in opts, value("--quat-scale", 1.0),
                  "--no-opacity" not in opts, int(value("--seed", 1)))
    elif kind == "mask":
        write_mask(out, int(argv[3]), int(argv[4]), int(argv[5]))
    elif kind == "cameras":
        write_cameras(out, argv[3:])
    elif kind == "png":
        write_png(out, int(argv[3]), int(argv[4]))
    else:
        sys.exit("unknown kind " + kind)


if __name__ == "__main__":
    main(sys.argv)
