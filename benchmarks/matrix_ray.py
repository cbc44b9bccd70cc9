"""The benchmark's cells as Ray tasks: two trainings a GPU, on this machine's GPUs or on a Ray cluster (--ray-address).

Why Ray: a scene's matrix is about five full trainings, and cells of different scenes, seeds and methods are
independent once their shared stages are done; run one after another they leave every GPU but one idle. The
dependency graph per scene and seed: one `base` task (train, remove), one `holes` task after it, then one `inpaint`
task per inpainter and source (after `holes` for the removed renders, after `base` for the input images: the direct
baseline's inpainting, the matrix's longest, need not wait for the masks), then one task per cell; training tasks
ask Ray for half of what is left of a GPU once inpainting tasks have a sliver (TRAININGS_PER_GPU; a CPU each where
the cluster has none: `task_resources`), and Ray sets CUDA_VISIBLE_DEVICES, so the engine processes a task starts
see only its GPU. The tasks call the same Stages and run_cell as the serial path, so work on disk is skipped the
same way and an interrupted run resumes; a failed stage fails its cells with its one-line reason, as serially.
Workers find this folder and the repository through PYTHONPATH.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Iterator
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
# what a worker on another node of a cluster would not inherit from this process: the engine's Python, the
# weights' folders and model paths (SPLATFILL_*), and the inpainters' own model variables
PASSED = ("LAMA_MODEL", "DIFFUSION_MODEL", "GEMINI_API_KEY")


def _stages(scene: str, seed: int, work: str, args: argparse.Namespace):
    from benchmarks.matrix_stages import Stages

    return Stages(Path(scene), seed, Path(work), args)


def _reason(step) -> str:
    """'' when `step()` ran, else its one-line reason (the cells that depend on it fail with it)."""
    from addon.engine_call import EngineError

    try:
        step()
    except EngineError as exc:
        return str(exc)
    return ""


def base_task(scene: str, seed: int, work: str, args: argparse.Namespace) -> str:
    """Train and remove for one scene and seed; '' or the failure's reason."""
    return _reason(_stages(scene, seed, work, args).base)


def holes_task(failed: str, scene: str, seed: int, work: str, args: argparse.Namespace) -> str:
    return failed or _reason(_stages(scene, seed, work, args).holes)


def inpaint_task(failed: str, scene: str, seed: int, inpainter: str, source: str, work: str,
                 args: argparse.Namespace) -> str:
    return failed or _reason(lambda: _stages(scene, seed, work, args).inpaint(inpainter, source))


def cell_task(failed: str, scene: str, seed: int, inpainter: str, method: str, work: str,
              args: argparse.Namespace) -> dict:
    from benchmarks.matrix_stages import run_cell

    return run_cell(_stages(scene, seed, work, args), method, inpainter, args, failed=failed)


# the share of a GPU a light inpainting task asks for; training tasks (base runs, cells) ask for the rest. The
# inpainters without model weights are CPU work (OpenCV, and exemplar's patch search), so a whole GPU for them
# kept the cells waiting (the first cell started about 200 s after the base runs). With these shares such an
# inpainting runs beside the trainings on a GPU (TRAININGS_PER_GPU of them). Model inpainters (LaMa, diffusion)
# ask for a training's share, as a training would.
INPAINT_GPU_SHARE = 0.01
# training stages on one GPU at once, by default. A step at 300k Gaussians is bound by the host (6.1 ms, 4.9 ms of
# kernels), so two processes keep a GPU busier: livingroom's whole matrix on one H200 took 785 s with one at a
# time and 603 / 595 s with two (two runs), 586 s with three, whose cells each took longer (docs/BENCHMARKS.md,
# "Matrix wall time"). Two at once measured slower when a step was still bound by its kernels.
TRAININGS_PER_GPU = 2


def light(inpainter: str) -> bool:
    """Whether an inpainter may share a GPU with a training: it loads no model weights and needs no GPU."""
    from engine.inpaint.registry import classes

    kind = classes().get(inpainter)  # an unknown name fails in its task, with the engine's message
    return kind is not None and not kind.needs.weights and not kind.needs.gpu


def task_resources(gpus: float, trainings_per_gpu: int = TRAININGS_PER_GPU) -> dict[str, dict]:
    """What each kind of task asks Ray for on a cluster with `gpus` GPUs: an equal share of a GPU for training
    stages (`trainings_per_gpu` at once), a small share of one for inpainting (so Ray still gives it a GPU of its
    own node to see), a CPU each where there are none."""
    if gpus < 1:
        return {"train": {"num_cpus": 1}, "inpaint": {"num_cpus": 1}}
    return {"train": {"num_gpus": (1 - INPAINT_GPU_SHARE) / trainings_per_gpu},
            "inpaint": {"num_gpus": INPAINT_GPU_SHARE}}


def start(args: argparse.Namespace) -> dict[str, dict]:
    """Connect to (or start) Ray with workers that import this folder; the resources each kind of task asks for."""
    import ray

    path = os.pathsep.join(p for p in (str(REPO), os.environ.get("PYTHONPATH", "")) if p)
    env = {"PYTHONPATH": path, **{k: v for k, v in os.environ.items() if k in PASSED or k.startswith("SPLATFILL_")}}
    ray.init(address=args.ray_address or None, runtime_env={"env_vars": env}, include_dashboard=False,
             logging_level="ERROR", log_to_driver=False)
    return task_resources(ray.cluster_resources().get("GPU", 0), args.trainings_per_gpu)


def run_cells(matrix: list[tuple[Path, int, str, str]], sources: dict[str, str], work: Path,
              args: argparse.Namespace) -> Iterator[tuple[int, dict]]:
    """(index in `matrix`, cell record) as each cell finishes; `sources` maps a method to the inpainting it
    reads ("removed" or "input")."""
    import ray

    resources = start(args)
    # no retries: a stage half done by a worker that died is not safe to start again in the same folder (the
    # engine refuses); run the benchmark again instead, which resumes from what is on disk
    # the hole masks are CPU work (numpy over the views' depth), so they ask for what a light inpainting does
    base, holes, inpaint, heavy, cell = (ray.remote(max_retries=0, **resources[kind])(f) for f, kind in (
        (base_task, "train"), (holes_task, "inpaint"), (inpaint_task, "inpaint"), (inpaint_task, "train"),
        (cell_task, "train")))
    bases, masks, inpaints, pending = {}, {}, {}, {}
    for k, (scene, seed, inpainter, method) in enumerate(matrix):
        key = (str(scene), seed)
        if key not in bases:  # once per scene and seed (setdefault would start a task each time)
            bases[key] = base.remote(*key, str(work), args)
        step = (*key, inpainter, sources[method])
        if sources[method] == "removed" and key not in masks:
            masks[key] = holes.remote(bases[key], *key, str(work), args)
        if step not in inpaints:
            after = masks[key] if sources[method] == "removed" else bases[key]
            inpaints[step] = (inpaint if light(inpainter) else heavy).remote(after, *step, str(work), args)
        pending[cell.remote(inpaints[step], *key, inpainter, method, str(work), args)] = k
    try:
        while pending:
            done, _ = ray.wait(list(pending), num_returns=1)
            yield pending.pop(done[0]), ray.get(done[0])
    finally:
        ray.shutdown()
