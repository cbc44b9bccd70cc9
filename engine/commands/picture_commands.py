"""Commands that make pictures and videos from folders of renders."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from engine.base.errors import InputError
from engine.base.progress import emit


@dataclass
class CompareConfig:
    columns: list[str] = field(default_factory=list)  # LABEL=DIR, in order
    views: list[str] = field(default_factory=list)  # file names present in the folders
    out: str = ""  # PNG to write (--per-view: a new folder)
    per_view: bool = False  # one labelled PNG per view into the folder --out


def compare(config: CompareConfig) -> Path | None:
    from engine.pictures.compare_sheet import compare_frames, compare_sheet

    columns = []
    for column in config.columns:
        name, sep, folder = column.partition("=")
        if not sep:
            raise InputError(f"column {column!r} must read LABEL=DIR")
        columns.append((name, Path(folder)))
    if config.per_view:
        emit("done", stage="compare", out=str(compare_frames(columns, config.views, Path(config.out))))
        return None
    return compare_sheet(columns, config.views, Path(config.out))


@dataclass
class VideoConfig:
    frames: str = ""  # a folder of PNG frames, in the order of their names
    out: str = ""  # new .mp4 file
    fps: int = 24  # frames a second


def video(config: VideoConfig) -> None:
    from engine.pictures.video import write_mp4

    frames = sorted(Path(config.frames).glob("*.png"))
    out = Path(config.out)
    if out.exists():
        raise InputError(f"{out} exists: name a new file for the video")
    emit("done", stage="video", out=str(write_mp4(frames, out, config.fps)), frames=len(frames))


@dataclass
class ChartConfig:
    spec: str = ""  # JSON with width, height and items
    out: str = ""  # PNG to write


def chart(config: ChartConfig) -> Path:
    from engine.pictures.chart_png import chart_png

    return chart_png(Path(config.spec), Path(config.out))


@dataclass
class RenderConfig:
    ply: str = ""  # the splat file to render
    cameras: str = ""  # cameras.json (engine cameras)
    out: str = ""  # new folder for the PNGs
    device: str = "auto"  # auto | cuda | cpu


def render(config: RenderConfig) -> Path:
    from engine.render.render_views import render_to_folder

    return render_to_folder(Path(config.ply), Path(config.cameras), Path(config.out), config.device)
