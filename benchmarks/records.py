"""What every measurement script shares: the machine, code commit and command behind a record, one JSON file per
record, and the question's tables.md made from those files (docs/BENCHMARKS.md quotes it)."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
RESULTS = REPO / "docs" / "results"


def provenance() -> dict:
    """The device, the code's commit and the exact command line, stored in every record."""
    import torch

    from engine.base.versions import code_commit

    return {"device": torch.cuda.get_device_name() if torch.cuda.is_available() else "cpu",
            "torch": torch.__version__, "commit": code_commit(), "command": "python " + shlex.join(sys.argv)}


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
