"""Reading vbrain's .vbo meshes (its OBJ subset: o, v, vn, f) for the build scripts beside this."""
import numpy as np


def read_vbo(path):
    """Positions (n x 3, millimetres RAS) and triangles (m x 3, 0-based) of a .vbo file."""
    v, f = [], []
    for line in open(path):
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:4]])
        elif line.startswith("f "):
            f.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.array(v), np.array(f, np.int64)
