"""Completion methods as plug-ins: one file in engine/complete/methods/ (or on SPLATFILL_PLUGINS) per method.

A method is a `CompletionMethod` subclass decorated with `@register`. Its class attributes declare what the
CLI, the benchmark, the Blender menus and the README's table show (name, label, summary, options, needs,
benchmark cells); its hooks say how it runs, over the one loop in engine.complete.run:

    check(job)          refuse bad options early (one-line InputError)
    keep_regions(job)   where the training images take the inpainted render (None: everywhere)
    after_scene(job, scene_dir)   change the training scene once written (COLMAP re-estimation); a report
    setup(job, settings)          the training settings and Trainer plug-ins (engine.train.trainer)
    after_train(job)              change the trained run before it is scored (the from-scratch graft); a report

This module and the method files import neither torch nor OpenCV at their top (hooks import what they need
when they run), so Blender's Python (scripts/benchmark.py) reads the registry too.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, ClassVar

from engine.base.defaults import BEST_ON_MEAN
from engine.base.errors import InputError
from engine.base.plugins import Needs, Registry


@dataclass(frozen=True)
class Option:
    """One method option; it becomes the CLI flag --<name> (with _ as -), typed from its default."""

    name: str
    default: Any
    help: str
    choices: tuple = ()


class CompletionMethod:
    """Base of every completion method; see the module docstring for the hooks."""

    name: ClassVar[str] = ""  # --method value
    label: ClassVar[str] = ""  # short label for menus and tables (the paper's prefix: Init, FT, Direct)
    summary: ClassVar[str] = ""
    source: ClassVar[str] = "removed"  # the inpainting it reads: "removed" renders' holes, or "input" images
    options: ClassVar[tuple[Option, ...]] = ()
    needs: ClassVar[Needs] = Needs()
    cells: ClassVar[dict[str, dict]] = {}  # benchmark cell key -> options, e.g. {"ft3": {"refs": 3}}

    def title(self, inpainter: str, options: dict) -> str:
        """The method's name in results, as the paper writes it (it also names the output folder)."""
        return f"{self.label}-{inpainter}"

    def short(self, options: dict) -> bool:
        """Whether it continues from the base run's scene and so trains for a tenth of its steps unless --steps
        is given (CompletionJob.short_steps): FT, and --warm's new scenes. The rest train a new scene from
        scratch for the base run's steps."""
        return bool(options.get("warm"))

    def check(self, job) -> None:
        """Refuse options that cannot work, before anything is written."""

    def keep_regions(self, job) -> dict | None:
        return None

    def after_scene(self, job, scene_dir: Path) -> dict | None:
        return None

    def after_train(self, job) -> dict | None:
        """Change the trained run before it is scored (a from-scratch scene grafted into the removed one); a
        report, or None."""
        return None

    def setup(self, job, settings):
        """(settings, Trainer plug-ins or None) of the training run; by default a new run with the
        original run's settings and step count."""
        return settings, None


def fill_hint(run: str) -> str:
    """The command that fills the hole, with the best tuning mean."""
    return (f"to fill it: `complete --run {run} --method {BEST_ON_MEAN[0]} --inpainter {BEST_ON_MEAN[1]}` "
            f"after `inpaint --run {run} --inpainter {BEST_ON_MEAN[1]}` (the best mean m-PSNR on the tuning scenes)")


METHODS: Registry[CompletionMethod] = Registry("method", "engine.complete.methods")


def register(cls: type[CompletionMethod]) -> type[CompletionMethod]:
    return METHODS.add(cls.name, cls)


def methods() -> dict[str, CompletionMethod]:
    """Every registered method by name, sorted by name."""
    return {name: cls() for name, cls in METHODS.classes().items()}


def get(name: str) -> CompletionMethod:
    return METHODS.get(name)()


def all_options() -> dict[str, Option]:
    """Every method's options by name (a name two methods share must mean the same: same default)."""
    merged: dict[str, Option] = {}
    for method in methods().values():
        for option in method.options:
            if option.name in merged and merged[option.name].default != option.default:
                raise TypeError(f"option {option.name!r} has two defaults across methods")
            merged.setdefault(option.name, option)
    return merged


@dataclass(frozen=True)
class Cell:
    """One benchmark cell kind: a method with fixed options."""

    key: str
    method: str
    options: dict = field(default_factory=dict)


def benchmark_cells() -> dict[str, Cell]:
    return {key: Cell(key, m.name, dict(opts)) for m in methods().values() for key, opts in m.cells.items()}


def resolve_options(method: CompletionMethod, given: dict) -> dict:
    """The method's options from `given` (all methods' options, most at their defaults). An option of
    another method set away from its default is an error rather than silently ignored."""
    own = {o.name: o for o in method.options}
    known = all_options()
    for name, value in given.items():
        option = known.get(name)
        if name not in own and option is not None and value != option.default:
            flag = "--" + name.replace("_", "-")
            raise InputError(f"{flag} is not an option of --method {method.name} (its options: "
                             f"{', '.join(own) or 'none'})")
    resolved = {name: given.get(name, o.default) for name, o in own.items()}
    for name, value in resolved.items():
        if own[name].choices and value not in own[name].choices:
            raise InputError(f"--{name.replace('_', '-')} {value!r} unknown: choose from "
                             f"{', '.join(map(str, own[name].choices))}")
    return resolved
