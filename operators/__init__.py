"""Thin operators: read properties, call one function, report. The work happens in the engine."""

from __future__ import annotations


def _modules():
    from . import capture, check_engine, panel, pipeline, setup_engine

    return (check_engine, setup_engine, pipeline, capture, panel)


def register() -> None:
    for module in _modules():
        module.register()


def unregister() -> None:
    for module in reversed(_modules()):
        module.unregister()
