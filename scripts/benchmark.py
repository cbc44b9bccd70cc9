"""The benchmark matrix: scene x method x inpainter x seed, through the engine, resumable, with tables
(benchmarks/matrix.py holds it; its docstring says what it writes).

    blender -b -P scripts/benchmark.py -- --scenes DIR... --methods init ft3 --inpainters fsr --seeds 0 1 --out DIR
    python scripts/benchmark.py --scenes DIR... ...          # the same with any Python (no torch needed here)
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from blender_entry import add_repo_to_path  # noqa: E402

add_repo_to_path()
from benchmarks.matrix import main  # noqa: E402

if __name__ == "__main__":
    sys.exit(main())
