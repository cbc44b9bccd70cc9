"""Where every file of a scene folder and of a run folder lives: the one place that spells their names.

The engine's stages, the scripts and the Blender add-on (numpy only) all ask these classes for paths, so
a folder's layout can change here alone. Each class wraps a root folder and only builds paths: nothing
here reads or writes.

A scene folder (made by scripts/make_scene.py, or any COLMAP capture):
    images/  gt/  masks/ (+ objects.json)  depth/  gt_depth/  holes/  sparse/0/  split.json  scene.json
make_scene.py's raw renders, before `build-scene`: with/ without/ cameras.json split.json objects.json meta.json
A run folder (`python -m engine train`), and what each later stage adds to it:
    config.json checkpoints/ point_cloud.ply classifier.npz objects.json metrics.json    train
    segments/  ids.npy masks/ objects.json segments.json (objects without ground truth)    segment
    removed/   point_cloud.ply images/ depth/ masks/ removal.json sheet.png              remove
    holes/     <view>.png (255 = hole) unseen/ holes.json sheet.png                       holes
    inpainted/<inpainter>/ and inpainted/direct-<inpainter>/                              inpaint
               images/ depth/ config.json sheet_test.png sheet_train.png
    complete/<Method name>/  scene/ (a scene folder) run/ (a run folder) renders/ scores.json   complete
               [recolmap.json]
    exports/   <stage>.ply .compressed.ply .splat .spz (for other splat tools)            export
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

RGB, DEPTH, MASKS = "images", "depth", "masks"



def _at(name: str, doc: str = "", kind: str = "") -> property:
    """A property: `name` inside the layout's root, as a path or as the layout class named `kind` of that folder
    (named, since layouts refer to ones defined further down). The one place each name is spelled."""
    return property(lambda self: globals()[kind](self.root / name) if kind else self.root / name, doc=doc or None)

@dataclass(frozen=True)
class _Folder:
    root: Path

    def __post_init__(self) -> None:
        object.__setattr__(self, "root", Path(self.root))


@dataclass(frozen=True)
class Views(_Folder):
    """A folder of per-view pictures named like the scene's images: RGB, z-depth and masks."""

    @property
    def images(self) -> Path:
        return self.root / RGB

    @property
    def depth(self) -> Path:
        return self.root / DEPTH

    @property
    def masks(self) -> Path:
        return self.root / MASKS

    sheet = _at("sheet.png")


@dataclass(frozen=True)
class SceneLayout(Views):
    """A scene folder: input views, their ground truth, and the COLMAP model."""

    gt = _at("gt")
    gt_depth = _at("gt_depth")
    holes = _at("holes")
    effects = _at("effects",
               "Per gt view, the pixels outside the target that removing it changed (shadow, reflection).")
    unseen = _at("unseen",
               "Per test view, the pixels no training view saw (the scores' seen-only PSNR leaves them out).")
    sparse = _at("sparse")

    @property
    def objects_json(self) -> Path:
        return self.masks / "objects.json"

    split_json = _at("split.json")
    scene_json = _at("scene.json")



@dataclass(frozen=True)
class CaptureLayout(SceneLayout):
    """`capture`'s output: a scene (images/, sparse/0/) made from photos, with how it was made."""

    config_json = _at("config.json")
    report = _at("capture.json", "Written last: a folder with capture.json is a finished capture.")
    work = _at(".sfm", "SfM's database and the phases finished, while the capture runs (removed when it is done).")


@dataclass(frozen=True)
class RendersLayout(_Folder):
    """make_scene.py's raw renders, which `python -m engine build-scene` turns into a scene folder:
    multi-part EXRs of every view with the target (with/) and of the ground-truth views without it
    (without/), the cameras, the split, the objects and the generator's settings."""

    with_object = _at("with")
    without_object = _at("without")
    cameras_json = _at("cameras.json")
    split_json = _at("split.json")
    objects_json = _at("objects.json")
    meta_json = _at("meta.json", "The generator's settings; the scene folder keeps them as scene.json.")


@dataclass(frozen=True)
class SegmentsLayout(Views):
    """`segment`'s output: objects found after training (engine.segment.run), which the run then uses in
    place of its scene's own masks and objects."""

    ids = _at("ids.npy", "(N,) uint8 object id per Gaussian of the run's point_cloud.ply (0 = background).")
    objects_json = _at("objects.json")
    report = _at("segments.json")


@dataclass(frozen=True)
class RemovedLayout(Views):
    """`remove`'s output: the remaining Gaussians, their renders and the removed object's region per view."""

    point_cloud = _at("point_cloud.ply")
    report = _at("removal.json")
    effects = _at("effects",
               "What the object did to its surroundings (its shadow), relit in this removal.", "EffectsLayout")


@dataclass(frozen=True)
class _MaskFolder(_Folder):
    """A stage's per-view masks (PNGs named like the views' images, 255 = in), its report and a sheet."""

    report_name = ""

    def mask(self, view: str) -> Path:
        return self.root / view

    sheet = _at("sheet.png")

    @property
    def report(self) -> Path:
        return self.root / self.report_name


@dataclass(frozen=True)
class HolesLayout(_MaskFolder):
    """`holes`' output: per view, the pixels no training view saw behind the removed object."""

    report_name = "holes.json"

    def unseen(self, view: str) -> Path:
        """The mask's unseen part alone (what no training view saw), without the see-through marks: the
        part the truth's holes/ score, kept so a wrong mask can be taken apart afterwards."""
        return self.root / "unseen" / view


@dataclass(frozen=True)
class EffectsLayout(_MaskFolder):
    """Inside `remove`'s output: per view, the pixels of what the object did to its surroundings (its
    shadow, the darkening under it), which the removed scene was relit to undo."""

    report_name = "effects.json"


@dataclass(frozen=True)
class InpaintedLayout(Views):
    """`inpaint`'s output: the removed renders (or the input images) with their holes filled."""

    config_json = _at("config.json")

    def sheet_of(self, split: str) -> Path:
        return self.root / f"sheet_{split}.png"


@dataclass(frozen=True)
class RunLayout(_Folder):
    """A training run, and the folders each later stage adds to it."""

    config_json = _at("config.json")
    checkpoints = _at("checkpoints")
    point_cloud = _at("point_cloud.ply")
    classifier = _at("classifier.npz")
    objects_json = _at("objects.json")
    metrics_json = _at("metrics.json")
    segments = _at("segments", "", "SegmentsLayout")
    previous_segments = _at("segments.previous",
               "The objects a later `segment` replaced or extended, kept for `segment --restore`.", "SegmentsLayout")
    removed = _at("removed", "", "RemovedLayout")
    holes = _at("holes", "", "HolesLayout")


    def inpainted(self, inpainter: str, source: str = "removed") -> InpaintedLayout:
        """`source` "removed" fills the holes of the removed renders; "input" paints the object out of the
        input images (the direct baseline), kept apart as direct-<inpainter>."""
        return InpaintedLayout(self.root / "inpainted" / (inpainter if source == "removed" else f"direct-{inpainter}"))

    def complete(self, method_name: str) -> CompleteLayout:
        return CompleteLayout(self.root / "complete" / method_name)

    exports = _at("exports", "`export`'s files for other splat tools, by default (engine.convert.export).")


@dataclass(frozen=True)
class CompleteLayout(_Folder):
    """`complete`'s output for one method: the scene it trained on, that training run, and the scores."""

    scene = _at("scene", "", "SceneLayout")
    run = _at("run", "", "RunLayout")
    renders = _at("renders")
    scores_json = _at("scores.json", "Written last: a folder with scores.json is a finished completion.")
    recolmap_json = _at("recolmap.json",
               "--recolmap: how many views COLMAP registered and their pose error (kept for a resumed run).")


def run_of(ply: Path) -> RunLayout | None:
    """The run a .ply belongs to: its own folder (RUN/point_cloud.ply) or the one above it (RUN/removed/...),
    whichever holds a classifier.npz or a config.json; None for a .ply from elsewhere."""
    for folder in (Path(ply).parent, Path(ply).parent.parent):
        run = RunLayout(folder)
        if run.classifier.is_file() or run.config_json.is_file():
            return run
    return None
