"""What every measurement script shares: the machine, code commit and command behind a record, one JSON file per
record, and the question's tables.md made from those files (docs/BENCHMARKS.md quotes it)."""

from __future__ import annotations

import argparse
import json
import shlex
import sys
from collections.abc import Callable
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
RESULTS = REPO / "docs" / "results"


def provenance() -> dict:
    """The device, the code's commit and the exact command line, stored in every record."""
    import torch

    from engine.base.versions import code_commit

    return {"device": torch.cuda.get_device_name() if torch.cuda.is_available() else "cpu",
            "torch": torch.__version__, "commit": code_commit(), "command": "python " + shlex.join(sys.argv)}


def run_study_args(doc: str) -> argparse.Namespace:
    """`SCRIPT RUN OUT [--device D]`, the arguments of a study that reads a trained run where it was trained and
    writes one small file to carry home (benchmarks/subject_inputs.py, benchmarks/floaters.py)."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("run")
    parser.add_argument("out")
    parser.add_argument("--device", default="auto")
    return parser.parse_args()


def option(args: list[str], flag: str) -> tuple[str | None, list[str]]:
    """The value after `flag` (None where absent) and the arguments without the two: the scoring scripts'
    (hole_error.py, removal_score.py) optional flags beside their positional ones."""
    if flag not in args:
        return None, args
    at = args.index(flag)
    return args[at + 1], args[:at] + args[at + 2:]


def save_record(results: Path, name: str, record: dict) -> None:
    results.mkdir(parents=True, exist_ok=True)
    (results / f"{name}.json").write_text(json.dumps(record, indent=1))
    print(json.dumps(record), flush=True)


def load_records(results: Path) -> list[dict]:
    return [json.loads(p.read_text()) for p in sorted(results.glob("*.json"))]


def write_tables(results: Path, title: str, lines: list[str]) -> None:
    """Write `results`/tables.md: the question's table, made from its records alone."""
    path = results / "tables.md"
    path.write_text("\n".join([f"# {title}", "", *lines, ""]))
    print(f"wrote {path}")


def report_or_measure(parser: argparse.ArgumentParser, results: Path, report: Callable[[Path], None],
                      measure: Callable[[argparse.Namespace], None]) -> int:
    """The entry every record-keeping tool shares: --results DIR (default `results`) and --report, which makes
    DIR/tables.md from the records there instead of measuring; otherwise `measure(args)` writes records."""
    parser.add_argument("--results", default=str(results), help="the records' folder")
    parser.add_argument("--report", action="store_true", help="make RESULTS/tables.md from its records only")
    args = parser.parse_args()
    if args.report:
        report(Path(args.results))
    else:
        measure(args)
    return 0


def shrink_pictures(folder: Path, width: int = 1600) -> int:
    """Every PNG under `folder` as a JPEG at most `width` px wide in its place (quality 85), so the records one
    call of the GPU machine returns fit in what it returns: three held-out scenes' PNG sheets were too large.
    Returns how many were converted."""
    import cv2

    count = 0
    for path in sorted(folder.rglob("*.png")):
        image = cv2.imread(str(path), cv2.IMREAD_COLOR)
        if image is None:
            continue
        if image.shape[1] > width:
            image = cv2.resize(image, (width, round(image.shape[0] * width / image.shape[1])),
                               interpolation=cv2.INTER_AREA)
        if cv2.imwrite(str(path.with_suffix(".jpg")), image, [cv2.IMWRITE_JPEG_QUALITY, 85]):
            path.unlink()
            count += 1
    return count


if __name__ == "__main__":  # python3 benchmarks/records.py shrink FOLDER (benchmarks/gpu.sh collect)
    if len(sys.argv) != 3 or sys.argv[1] != "shrink":
        sys.exit("usage: python3 benchmarks/records.py shrink FOLDER")
    print(f"pictures as JPEG: {shrink_pictures(Path(sys.argv[2]))}")
