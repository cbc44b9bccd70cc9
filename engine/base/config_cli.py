"""Command-line options made from settings dataclasses, so a setting is declared and explained in one place: its
field's type and default give the option's type, the comment on its line gives the option's help, and the
parsed options give the dataclass back. Every engine command's parser is built here (engine.cli's table)."""

from __future__ import annotations

import argparse
import ast
import dataclasses
import importlib
import inspect
import io
import textwrap
import tokenize
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Command:
    """One engine command: `python -m engine NAME`, its settings and what runs it.

    `config` and `run` are "module:name" strings, imported only when the parser is built or the command runs.
    `run(config)` returns a line for the user (str), a written file or folder (printed as "wrote PATH"), a report
    dict (printed through `done`, a format string given `config` and the report's keys), or None."""

    name: str
    summary: str
    config: str
    run: str
    required: tuple[str, ...] = ()
    skip: tuple[str, ...] = ()  # fields that `arguments` declares itself
    done: str = ""
    arguments: str = ""  # "module:function(parser)" adding options the dataclass does not declare
    from_args: str = ""  # "module:function(args) -> config" where the options are more than the fields


def load(ref: str) -> Any:
    """The object a "module:name" string names."""
    module, _, name = ref.partition(":")
    return getattr(importlib.import_module(module), name)


def field_help(cls) -> dict[str, str]:
    """Each field's one-line meaning: the comment on its line, else the comment lines just above it, read from the
    class's source (its own and its bases'), so the dataclass is the one place a setting is explained."""
    meanings: dict[str, str] = {}
    for klass in reversed(cls.__mro__[:-1]):
        if dataclasses.is_dataclass(klass):
            meanings.update(_class_comments(klass))
    return meanings


def _class_comments(klass) -> dict[str, str]:
    lines, _ = inspect.getsourcelines(klass)
    comments = {tok.start[0]: tok.string.lstrip("# ").strip()
                for tok in tokenize.generate_tokens(io.StringIO("".join(lines)).readline)
                if tok.type == tokenize.COMMENT}
    code = {i + 1 for i, line in enumerate(lines) if line.strip() and not line.strip().startswith("#")}
    meanings = {}
    for node in ast.parse(textwrap.dedent("".join(lines))).body[0].body:
        if not isinstance(node, ast.AnnAssign) or not isinstance(node.target, ast.Name):
            continue
        row = node.lineno
        text = comments.get(row)
        if text is None:
            above = []
            while row - 1 in comments and row - 1 not in code:
                row -= 1
                above.insert(0, comments[row])
            text = " ".join(above)
        meanings[node.target.id] = text
    return meanings


def add_option(parser: argparse.ArgumentParser, name: str, default: Any, meaning: str, required: bool = False,
               choices: tuple = (), item: type = float) -> None:
    """--name (with _ as -) typed from its default: a bool as --x/--no-x, a list as values of `item`, else the
    default's type; its help the meaning and the default."""
    flag = f"--{name.replace('_', '-')}"
    meaning = meaning.replace("%", "%%")
    if isinstance(default, bool):
        parser.add_argument(flag, action=argparse.BooleanOptionalAction, default=default, help=meaning)
    elif isinstance(default, list):
        parser.add_argument(flag, type=item, nargs="+" if required else "*", default=default, required=required,
                            help=meaning)
    else:
        shown = f" (default: {default})" if default != "" and not required else ""
        parser.add_argument(flag, type=type(default), default=default, required=required,
                            choices=choices or None, help=(meaning + shown).strip())


def add_config_arguments(parser: argparse.ArgumentParser, cls, skip: tuple[str, ...] = (),
                         required: tuple[str, ...] = ()) -> None:
    """One option per field of the dataclass `cls` (add_option), its help the field's comment (field_help)."""
    meanings = field_help(cls)
    for f in dataclasses.fields(cls):
        if f.name in skip or f.type in ("dict", dict):
            continue
        listed = f.default_factory is not dataclasses.MISSING
        default = f.default_factory() if listed else f.default
        add_option(parser, f.name, default, meanings.get(f.name, ""), required=f.name in required,
                   item=str if "str" in str(f.type) else float)


def config_from_args(args: argparse.Namespace, cls):
    """The dataclass `cls` from parsed options (fields without an option keep their defaults)."""
    return cls(**{f.name: getattr(args, f.name) for f in dataclasses.fields(cls) if hasattr(args, f.name)})


def add_commands(parser: argparse.ArgumentParser, commands: list[Command]) -> None:
    """A sub-command per entry, its options from its dataclass (and its own `arguments`)."""
    sub = parser.add_subparsers(dest="command", required=True)
    for command in commands:
        p = sub.add_parser(command.name, help=command.summary)
        add_config_arguments(p, load(command.config), skip=command.skip, required=command.required)
        if command.arguments:
            load(command.arguments)(p)
        p.set_defaults(entry=command)


def run_command(command: Command, args: argparse.Namespace, say: Callable[[str], None]) -> None:
    """Run one parsed command and tell the user what it did."""
    config = load(command.from_args)(args) if command.from_args else config_from_args(args, load(command.config))
    result = load(command.run)(config)
    if isinstance(result, dict) and command.done:
        say(command.done.format_map({**result, "config": config}))
    elif isinstance(result, str):
        say(result)
    elif result is not None and not isinstance(result, dict):
        say(f"wrote {result}")
