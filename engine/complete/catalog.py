"""The plug-ins of stages 4 and 5 (inpainters, completion methods) described for the people and programs
that choose among them: `python -m engine plugins` gives the Blender add-on's menus their items as JSON,
and --markdown gives the README's table (a test keeps the README equal to it)."""

from __future__ import annotations

from engine.base.defaults import BEST_ON_MEAN, DEFAULT_INPAINTER, DEFAULT_METHOD, WHY
from engine.complete.registry import methods
from engine.inpaint.registry import classes


def describe() -> dict:
    """{"inpainters": [...], "methods": [...], "defaults": {...}}, each with its name, summary and needs; methods
    also with their label, the inpainting they read, their options and their benchmark cells; the defaults the
    tuning scenes chose and why (engine.base.defaults), which the add-on's menus offer first."""
    inpainters = [{"name": name, "summary": cls.summary, "needs": cls.needs.describe(), "uses_mask": cls.uses_mask}
                  for name, cls in classes().items()]
    completion = [{"name": m.name, "label": m.label, "summary": m.summary, "source": m.source,
                   "needs": m.needs.describe(), "cells": m.cells,
                   "options": [{"name": o.name, "default": o.default, "help": o.help, "choices": list(o.choices)}
                               for o in m.options]} for m in methods().values()]
    defaults = {"method": DEFAULT_METHOD, "inpainter": DEFAULT_INPAINTER, "best_on_mean": list(BEST_ON_MEAN),
                "why": WHY}
    return {"inpainters": inpainters, "methods": completion, "defaults": defaults}


def markdown_table() -> str:
    rows = ["| stage | name | what it does | needs |", "|---|---|---|---|"]
    plugins = describe()
    rows += [f"| complete | `{m['name']}` | {m['summary']} | {m['needs']} |" for m in plugins["methods"]]
    rows += [f"| inpaint | `{i['name']}` | {i['summary']} | {i['needs']} |" for i in plugins["inpainters"]]
    return "\n".join(rows)
