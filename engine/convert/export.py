"""`export`: a run's scene (as trained, removed, or completed by a method) as a file other splat tools open:
the standard INRIA .ply (without our 16 identity fields unless asked), SuperSplat's compressed .ply, .splat or
.spz (engine.formats.splat_files). The finished scene of a method lives at RUN/complete/<Method>/run/, which no
user should have to know: `--stage complete/<Method>` (or `--stage complete`, the only one there is) finds it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from engine.base.errors import InputError
from engine.base.progress import emit
from engine.formats.layout import RunLayout
from engine.formats.splat_files import FORMATS, SUFFIX, read_splat_file, write_splat_file


@dataclass
class ExportConfig:
    run: str = ""  # the training run
    stage: str = ""  # "" (as trained) | removed | complete/<Method> (complete alone: the only one) | a folder of
    # the run holding a point_cloud.ply (Blender's stamped removed-<object>-<time>/)
    format: str = "ply"  # ply | compressed-ply | splat | spz
    out: str = ""  # the file to write (default RUN/exports/<stage>.<format's suffix>)
    with_identities: bool = False  # .ply: keep the obj_dc_* identity fields (only our tools read them)
    sh_degree: int = -1  # SH bands to keep (-1: all the scene has; .splat keeps none)


def stage_ply(run: RunLayout, stage: str) -> Path:
    """The .ply of a run's stage, with a one-line error that lists what there is."""
    if stage in ("", "trained"):
        path = run.point_cloud
    elif stage == "removed":
        path = run.removed.point_cloud
    elif stage == "complete" or stage.startswith("complete/"):
        done = sorted(p.parent.name for p in run.root.glob("complete/*/scores.json"))
        name = stage.partition("/")[2] or (done[0] if len(done) == 1 else "")
        if name not in done:
            raise InputError(f"{run.root} has no finished completion {name or '(several or none)'}; give "
                             f"--stage complete/<Method>, one of: {', '.join(done) or 'none yet (run complete)'}")
        path = run.complete(name).run.point_cloud
    elif RunLayout(run.root / stage).point_cloud.is_file():
        path = RunLayout(run.root / stage).point_cloud
    else:
        raise InputError(f"--stage {stage}: give removed, complete/<Method>, a folder of {run.root} holding a "
                         "point_cloud.ply, or nothing for the trained scene")
    if not path.is_file():
        raise InputError(f"{path} does not exist: run that stage first")
    return path


def export(config: ExportConfig) -> Path:
    """Write the stage's Gaussians as `config.format`; returns the file written."""
    if config.format not in FORMATS:
        raise InputError(f"--format {config.format}: give one of {', '.join(FORMATS)}")
    run = RunLayout(config.run)
    source = stage_ply(run, config.stage)
    stage = Path(config.stage)  # a folder named by its path is named by its own name
    stem = stage.name if stage.is_absolute() else (config.stage or "trained").replace("/", "-")
    out = Path(config.out) if config.out else run.exports / f"{stem}{SUFFIX[config.format]}"
    if out.resolve() == source.resolve():
        raise InputError(f"--out {out} is the scene being exported: write it elsewhere")
    out.parent.mkdir(parents=True, exist_ok=True)
    vertices = read_splat_file(source)
    write_splat_file(out, vertices, config.format, None if config.sh_degree < 0 else config.sh_degree,
                     config.with_identities)
    emit("done", stage="export", out=str(out), format=config.format, gaussians=len(vertices))
    return out
