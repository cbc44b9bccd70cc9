"""FT-<inpainter>(3 | All): finetune the removed scene into its hole from the reference views' inpainting,
the removed Gaussians frozen for real (engine.complete.finetune has the losses and why). The perceptual term is
ST-LPIPS by default: its weights come with the set-up, where LPIPS's backbone must be supplied, and the benchmark
table measured it. Any term other than the paper's LPIPS is in the name: FT-<inpainter>(3)[st-lpips],
FT-<inpainter>(3)[l1]."""

from __future__ import annotations

from engine.base.plugins import Needs
from engine.complete.registry import CompletionMethod, Option, register

PERCEPTUAL = ("lpips", "st-lpips", "l1")


@register
class Finetune(CompletionMethod):
    name = "ft"
    label = "FT"
    summary = "finetune the removed scene into the hole, its Gaussians frozen (the paper's FT)"
    options = (Option("refs", 3, "reference views: the training views with the largest holes (0 = all with a hole)"),
               Option("perceptual", "st-lpips", "the term on non-reference views", PERCEPTUAL))
    needs = Needs(weights=("ST-LPIPS weights from the set-up (--perceptual lpips: an LPIPS backbone; l1: none)",))
    cells = {"ft3": {"refs": 3}, "ftall": {"refs": 0}}

    def short(self, options: dict) -> bool:
        return True

    def title(self, inpainter: str, options: dict) -> str:
        tag = "" if options["perceptual"] == "lpips" else f"[{options['perceptual']}]"
        return f"FT-{inpainter}({options['refs'] or 'All'}){tag}"

    def after_train(self, job) -> dict | None:
        """The new Gaussians kept to the hole (engine.complete.warm_start.confine); the removed scene is fixed."""
        from engine.complete.warm_start import confine

        return confine(job, warm=False)

    def setup(self, job, settings):
        from engine.complete.finetune import finetune_setup
        from engine.complete.warm_start import no_hole_setup

        setup = finetune_setup(settings, job.original, job.removed, job.inpainted, job.holes, job.options["refs"],
                               job.options["perceptual"], job.short_steps(), job.config.seed, job.device,
                               (job.config.lpips_backbone, job.config.lpips_heads))
        return setup if setup is not None else no_hole_setup(job, settings)  # no hole: the removed scene stays
