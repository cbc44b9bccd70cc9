"""Whether a completion should keep the removed render in the hole where it already looks like the hole's
surroundings (`inpaint --keep Z`, engine.inpaint.keep), and at which Z: chosen on tuning seeds, then reported on
held-out ones, in one batch on the GPU machine.

Takes finished matrix runs (scripts/benchmark.py with Ref-telea: each RUN has removed/, holes/ and the cell
complete/Ref-telea[warm]); for each Z inpaints RUN/inpainted/telea-keepZ and completes it with Ref (warm, the
defaults) into RUN/complete/Ref-telea-keepZ, several at once on every GPU. Z = 0 is the matrix's own Ref-telea
cell. The Z with the best mean m-PSNR (true hole, test views) over the tuning runs is then run on the held-out
runs; the JSON holds every cell beside each run's unfilled hole.

    PYTHONPATH=. python benchmarks/keep_sweep.py --tuning RUN... --heldout RUN... [--z 0.5 1 2] [--per-gpu 4] --json OUT
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from engine.complete.registry import get, resolve_options
from engine.formats.layout import CompleteLayout, RunLayout

REFERENCE = get("reference")
PLAIN = REFERENCE.title("telea", resolve_options(REFERENCE, {}))  # the matrix's Ref-telea cell at its defaults: Z = 0


def _gpus() -> int:
    try:
        return max(1, len(subprocess.run(["nvidia-smi", "-L"], capture_output=True, text=True).stdout.splitlines()))
    except FileNotFoundError:
        return 1


def cell(run: Path, z: float) -> CompleteLayout:
    """The completion of `run` at keep `z` (0: the matrix's plain Ref-telea)."""
    return RunLayout(run).complete(PLAIN if z == 0 else f"Ref-telea-keep{z:g}")


def complete(run: Path, z: float, gpu: int, device: str) -> str:
    """Inpaint with --keep z and complete with Ref; '' or the failing stage's last lines."""
    inpainted = RunLayout(run).inpainted(f"telea-keep{z:g}").root
    env = {**os.environ, "CUDA_VISIBLE_DEVICES": str(gpu)}
    steps = [["inpaint", "--run", str(run), "--inpainter", "telea", "--keep", f"{z:g}", "--out", str(inpainted)],
             ["complete", "--run", str(run), "--method", "reference", "--inpainter", "telea", "--inpainted",
              str(inpainted), "--out", str(cell(run, z).root), "--device", device, "--no-turntable"]]
    for args in steps:
        if args[0] == "inpaint" and inpainted.is_dir():
            continue
        done = subprocess.run([sys.executable, "-m", "engine", *args], env=env, capture_output=True, text=True)
        if done.returncode:
            return f"{args[0]}: {(done.stdout + done.stderr)[-600:]}"
    return ""


def scores(run: Path, z: float) -> dict:
    """m-PSNR of the cell and of the unfilled hole, from the cell's scores.json."""
    report = json.loads(cell(run, z).scores_json.read_text())
    return {"m_psnr": report["scores"]["m_psnr"], "unfilled": report["removed_scores"]["m_psnr"],
            "psnr_kept": report["scores"].get("psnr_kept")}


def batch(runs: list[Path], zs: list[float], per_gpu: int, device: str) -> dict:
    """Every (run, z) completed, per_gpu at once on each GPU; {run: {z: scores or error}}."""
    jobs = [(run, z) for run in runs for z in zs if z != 0 and not cell(run, z).scores_json.is_file()]
    gpus = _gpus()
    with ThreadPoolExecutor(gpus * per_gpu) as pool:
        done = pool.map(lambda job: complete(*job[1], job[0] % gpus, device), enumerate(jobs))
        errors = dict(zip(jobs, done, strict=True))
    table: dict = {}
    for run in runs:
        for z in zs:
            error = errors.get((run, z), "")
            table.setdefault(str(run), {})[f"{z:g}"] = {"error": error} if error else scores(run, z)
            print(run, z, table[str(run)][f"{z:g}"], flush=True)
    return table


def mean_of(table: dict, z: float) -> float:
    values = [cells[f"{z:g}"].get("m_psnr") for cells in table.values()]
    return float(np.mean(values)) if values and None not in values else float("-inf")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tuning", nargs="+", type=Path, required=True)
    parser.add_argument("--heldout", nargs="*", type=Path, default=[])
    parser.add_argument("--z", nargs="+", type=float, default=[0.5, 1.0, 2.0])
    parser.add_argument("--per-gpu", type=int, default=4)
    parser.add_argument("--device", default="cuda")
    parser.add_argument("--json", type=Path, required=True)
    args = parser.parse_args()
    zs = [0.0, *args.z]
    tuning = batch(args.tuning, zs, args.per_gpu, args.device)
    chosen = max(zs, key=lambda z: mean_of(tuning, z))
    print("chosen on the tuning runs: Z =", chosen, flush=True)
    heldout = batch(args.heldout, sorted({0.0, chosen}), args.per_gpu, args.device) if args.heldout else {}
    args.json.write_text(json.dumps({"z": zs, "chosen": chosen, "tuning": tuning, "heldout": heldout,
                                     "tuning_means": {f"{z:g}": mean_of(tuning, z) for z in zs}}, indent=1))


if __name__ == "__main__":
    main()
