"""Minimal binary PLY reader for the accuracy bench (numpy only): the vertex element of a 3DGS PLY
as a structured array. Independent of al-refine's reader on purpose (the baselines must not share
code with the engine they are compared to)."""
import numpy as np

_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
          "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
          "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_vertices(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, count, props, in_vertex = None, 0, [], False
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            words = line.decode("ascii").split()
            if not words or words[0] == "comment":
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                in_vertex = words[1] == "vertex"
                if in_vertex:
                    count = int(words[2])
            elif words[0] == "property" and in_vertex:
                props.append((words[2], _TYPES[words[1]]))
            elif words[0] == "end_header":
                break
        if fmt not in ("binary_little_endian", "binary_big_endian"):
            raise ValueError(f"{path}: only binary PLY is read here (format {fmt})")
        end = "<" if fmt == "binary_little_endian" else ">"
        dtype = np.dtype([(n, end + t) for n, t in props])
        return np.fromfile(f, dtype=dtype, count=count)


def positions(v):
    return np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64)


def features(v, prefix="semantic_"):
    names = sorted((n for n in v.dtype.names if n.startswith(prefix) and n[len(prefix):].isdigit()),
                   key=lambda n: int(n[len(prefix):]))
    if not names:
        return None
    return np.stack([v[n] for n in names], 1).astype(np.float64)
