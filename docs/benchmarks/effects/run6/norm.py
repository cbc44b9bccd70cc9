import sys

import numpy as np
import torch

from engine.base.knn import knn
from engine.edit import effects as E

name = sys.argv[1]
d = np.load(f"/tmp/s4/d/{name}_shadow.npz")
plane = (d["plane_n"].astype(np.float64), float(d["plane_d"]))
pts, col = d["points"].astype(np.float64), d["colors"].astype(np.float64)
core = d["core"].astype(np.float64)
in_true = np.load(f"/tmp/s4/{name}_in_true.npy")
frame = E._Frame.of(*plane)
h = frame.height(core)
size = np.percentile(h, 98) - np.percentile(h, 2)
flat = frame.flat(core)
centre = np.median(flat, 0)
radius = np.percentile(np.linalg.norm(flat - centre, axis=1), 95)
reach = radius + 3 * size
hp, acr = frame.height(pts), frame.flat(pts)
rec = (np.linalg.norm(acr - centre, axis=1) < reach) & (hp > -0.15 * size) & (hp < 0.05 * size)
P, C, T = pts[rec], col[rec], in_true[rec]
ly = np.log(C @ E.LUMA + 1e-3)
chroma = C / (C.sum(1, keepdims=True) + 1e-3)


def auc(score, t):  # P(score of a true > score of a false)
    r = np.empty(len(score))
    r[np.argsort(score, kind="stable")] = np.arange(1, len(score) + 1)
    n1 = t.sum()
    n0 = (~t).sum()
    return (r[t].sum() - n1 * (n1 + 1) / 2) / (n1 * n0)


def local_median(feat, k):
    f = torch.as_tensor(feat, dtype=torch.float32)
    _, ids = knn(f, f, k)
    return np.median(ly[ids.numpy()], axis=1)


print(name, "receivers", rec.sum(), "true", T.sum(), f"size {size:.3f} radius {radius:.3f}")
print(f"A global  AUC {auc(-ly, T):.3f}")
for k in (100, 400):
    print(f"B chroma k={k} AUC %.3f" % auc(-(ly - local_median(chroma, k)), T))
fl = frame.flat(P)
for k in (100, 400, 1600):
    print(f"C space k={k} AUC %.3f" % auc(-(ly - local_median(fl, k)), T))
