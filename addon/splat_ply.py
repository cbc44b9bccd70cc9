"""Turn a 3DGS .ply (read by engine.formats.splat_ply, the reader the engine uses too) into what
Blender draws: position, rotation, scale, colour, opacity, SH bands and the identity group.

It needs no bpy, so the tests check it without Blender. The groups come from the run's classifier.npz
(the engine writes it numpy-only for this reason): argmax of the per-Gaussian class logits.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .formats import InputError, checks, layout, splat_files, splat_ply


@dataclass
class Splats:
    positions: np.ndarray  # (N, 3) float32
    rotations: np.ndarray  # (N, 4) float32 unit quaternions, w x y z
    scales: np.ndarray  # (N, 3) float32, standard deviations in world units
    colors: np.ndarray  # (N, 4) float32 RGB of the SH DC term as the engine renders it (sRGB-encoded picture
    # values, not clamped: the higher bands add to it before the clamp), alpha = opacity
    sh_rest: np.ndarray  # (N, K, 3) float32 coefficients of the SH bands above 0 (K = 0, 3, 8 or 15)
    groups: np.ndarray  # (N,) int32 identity group (0 without a classifier)
    names: dict[int, str]  # group id -> object name


def read_splats(path: Path) -> Splats:
    """The proxies' data for `path`, grouped by identity when a classifier.npz sits beside it or in the
    run folder above it (a removal's output lies in RUN/removed/)."""
    path = Path(path)
    v = splat_files.read_splat_file(path)
    columns = lambda prefix, n: np.stack([v[f"{prefix}{i}"] for i in range(n)], axis=1).astype(np.float32)  # noqa: E731
    rotations = columns("rot_", 4)
    rotations /= np.maximum(np.linalg.norm(rotations, axis=1, keepdims=True), 1e-12)
    rgb = 0.5 + splat_ply.SH_C0 * columns("f_dc_", 3)
    rest = len([n for n in v.dtype.names if n.startswith("f_rest_")]) // 3
    sh_rest = (columns("f_rest_", 3 * rest).reshape(len(v), 3, rest).transpose(0, 2, 1)  # channel-major in the file
               if rest else np.zeros((len(v), 0, 3), np.float32))
    alpha = 1.0 / (1.0 + np.exp(-v["opacity"].astype(np.float32)))
    groups = np.zeros(len(v), np.int32)
    names = {0: "background"}
    run = layout.run_of(path)
    identity = [f"obj_dc_{i}" for i in range(splat_ply.IDENTITY_DIM)]
    has_identity = all(n in v.dtype.names for n in identity)
    if run is not None and run.segments.objects_json.is_file():
        groups, names = _segment_groups(run, v, has_identity)
    elif run is not None and run.classifier.is_file() and has_identity:
        weight, bias = splat_ply.read_classifier(run.classifier)
        groups = (columns("obj_dc_", splat_ply.IDENTITY_DIM) @ weight.T + bias).argmax(1).astype(np.int32)
        names = _object_names(run, len(bias))
    return Splats(positions=np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float32), rotations=rotations,
                  scales=np.exp(columns("scale_", 3)), colors=np.concatenate([rgb, alpha[:, None]], 1),
                  sh_rest=np.ascontiguousarray(sh_rest), groups=groups, names=names)


def scene_of(ply: Path) -> Path | None:
    """The scene folder of the run a .ply belongs to (its config.json names it), if both are there."""
    run = layout.run_of(ply)
    try:
        scene = Path(checks.read_json(run.config_json)["scene"]) if run and run.config_json.is_file() else None
    except (InputError, KeyError, TypeError):
        return None
    return scene if scene is not None and scene.is_dir() else None


def _segment_groups(run: layout.RunLayout, v: np.ndarray, has_identity: bool) -> tuple[np.ndarray, dict[int, str]]:
    """Groups from the objects `engine segment` found: its per-Gaussian ids for the run's own .ply, the
    one-hot identities it gave the Gaussians for a .ply made from the run afterwards (removed, completed)."""
    names = {0: "background"}
    try:
        names.update({int(e["id"]): str(e["name"]) for e in checks.read_json(run.segments.objects_json)})
        ids = np.load(run.segments.ids) if run.segments.ids.is_file() else np.zeros(0)
    except (InputError, OSError, ValueError, KeyError, TypeError, OverflowError):
        return np.zeros(len(v), np.int32), {0: "background"}
    if len(ids) == len(v):
        return ids.astype(np.int32), names
    if has_identity and max(names) < splat_ply.IDENTITY_DIM:
        identity = np.stack([v[f"obj_dc_{i}"] for i in range(max(names) + 1)], axis=1)
        return identity.argmax(1).astype(np.int32), names
    return np.zeros(len(v), np.int32), names


def _object_names(run: layout.RunLayout, classes: int) -> dict[int, str]:
    """Names from the training scene's masks/objects.json (the run's config.json names the scene)."""
    names = {i: f"object_{i}" for i in range(classes)}
    names[0] = "background"
    try:
        scene = Path(checks.read_json(run.config_json)["scene"]) if run.config_json.is_file() else None
        entries = checks.read_json(layout.SceneLayout(scene).objects_json) if scene else []
        names.update({int(e["id"]): str(e["name"]) for e in entries if int(e["id"]) < classes})
    except (InputError, KeyError, TypeError, ValueError, OverflowError):
        return names
    return names
