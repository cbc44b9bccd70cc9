"""Thin operators: read properties, call one function, report. The work happens in the engine."""

from __future__ import annotations


def _modules():
    from . import check_engine, panel, pipeline

    return (check_engine, pipeline, panel)


def register() -> None:
    for module in _modules():
        module.register()


def unregister() -> None:
    for module in reversed(_modules()):
        module.unregister()
