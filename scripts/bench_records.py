"""What every benchmark script shares: the machine and command behind a record, one JSON file per record,
and its own marked section of docs/BENCHMARKS.md regenerated from those files."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
BENCHMARKS = REPO / "docs" / "BENCHMARKS.md"


def provenance() -> dict:
    """The device and the exact command line, stored in every record."""
    import torch

    return {"device": torch.cuda.get_device_name() if torch.cuda.is_available() else "cpu",
            "torch": torch.__version__, "command": "python " + shlex.join(sys.argv)}


def save_record(results: Path, name: str, record: dict) -> None:
    results.mkdir(parents=True, exist_ok=True)
    (results / f"{name}.json").write_text(json.dumps(record, indent=1))
    print(json.dumps(record), flush=True)


def load_records(results: Path) -> list[dict]:
    return [json.loads(p.read_text()) for p in sorted(results.glob("*.json"))]


def write_section(key: str, heading: str, lines: list[str]) -> None:
    """Replace the text between <!-- key:begin --> and <!-- key:end --> in BENCHMARKS.md with `lines`,
    appending a new `## heading` section the first time."""
    begin, end = f"<!-- {key}:begin -->", f"<!-- {key}:end -->"
    section = "\n".join([begin, *lines, end])
    text = BENCHMARKS.read_text() if BENCHMARKS.exists() else "# Benchmarks\n"
    if begin in text:
        text = text[: text.index(begin)] + section + text[text.index(end) + len(end):]
    else:
        text += f"\n## {heading}\n\n{section}\n"
    BENCHMARKS.write_text(text)
    print(f"wrote {BENCHMARKS}")
