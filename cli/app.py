"""The ``resal`` typer app, on which each command module registers its command, and the one-line usage errors of
every command: an unknown option or command, a missing argument, a value click refused."""

from __future__ import annotations

from typing import Any

import typer

from cli.common import _fail
from reproductions.errors import InputError


def _command_path(ctx: Any) -> str:
    """`resal fit drop`: the command a click context runs, named as the user typed it (a test runner's root too)."""
    names = []
    while ctx is not None and ctx.parent is not None:
        names.append(ctx.info_name)
        ctx = ctx.parent
    return " ".join(["resal", *reversed(names)])


def _usage_error(exc: Exception, given: list[str], ctx: Any = None) -> InputError | None:
    """Click's usage error ``exc`` (an unknown option or command, a missing argument, a value click refused) as one
    ``InputError``; None for any other exception, and for the help a group given nothing prints. ``given``: the
    arguments as typed, to quote an unknown option with its value; ``ctx``: the failing command's context when
    click did not attach it to ``exc``. (typer vendors click in recent versions: the classes are matched by name.)"""
    kinds = {c.__name__ for c in type(exc).__mro__}
    if "UsageError" not in kinds or "NoArgsIsHelpError" in kinds:
        return None
    ctx = getattr(exc, "ctx", None) or ctx
    path = _command_path(ctx)
    if "NoSuchOption" in kinds:
        opt = getattr(exc, "option_name", "") or "option"
        takes = sorted(o for q in (ctx.command.params if ctx is not None else ()) for o in q.opts
                       if o.startswith("--") and o != "--help")
        at = given.index(opt) if opt in given else -1
        where = f"{opt} {given[at + 1]}" if 0 <= at < len(given) - 1 and not given[at + 1].startswith("--") else opt
        guess = list(getattr(exc, "possibilities", None) or ())  # the closest first
        hint = f"; did you mean {' or '.join(guess)}?" if guess else ""
        return InputError(where, f"not an option of `{path}`{hint} (it takes "
                                 f"{', '.join(takes) if takes else 'no option but --help'})")
    if ctx is not None and hasattr(ctx.command, "commands") and "No such command" in str(exc):
        name = next((a for a in given if not a.startswith("-")), "")
        return InputError(f"command '{name}'", f"not a command of `{path}` (expected one of "
                                               f"{', '.join(ctx.command.commands)}; see {path} --help)")
    where = getattr(exc, "option_name", None) or path  # an option given without its value: the option
    return InputError(where, f"{exc.format_message()} (see {path} --help)")  # type: ignore[attr-defined]


class _OneLineGroup(typer.core.TyperGroup):
    """Every usage mistake gets one ``error:`` line and exit 2, as all bad input does, never click's usage screen:
    the group's own options, its command names, and (around each command it runs) the command's own arguments; so
    every command of the app, the ones added later too, behaves the same."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        given = list(args)  # click consumes the list
        try:
            return super().parse_args(ctx, args)
        except Exception as exc:
            err = _usage_error(exc, given, ctx)
            if err is None:
                raise
            _fail(err)

    def resolve_command(self, ctx: Any, args: list[str]) -> Any:
        try:
            return super().resolve_command(ctx, args)
        except Exception as exc:
            err = _usage_error(exc, list(args), ctx)
            if err is None:
                raise
            _fail(err)

    def invoke(self, ctx: Any) -> Any:
        given = [*ctx._protected_args, *ctx.args]
        try:
            return super().invoke(ctx)
        except Exception as exc:  # raised while the command parsed its arguments (or, rarely, while it ran)
            cmd = self.get_command(ctx, given[0]) if given else None
            sub = typer.Context(cmd, parent=ctx, info_name=given[0]) if cmd is not None else None
            err = _usage_error(exc, given, sub)
            if err is None:
                raise
            _fail(err)


# plain help (no rich markup): typer then skips its rich formatting imports, and `resal --help` stays under 0.3 s
app = typer.Typer(cls=_OneLineGroup, add_completion=False, no_args_is_help=True, pretty_exceptions_enable=False,
                  rich_markup_mode=None,
                  help="Reproduce H. Résal (1883), 'Commentaire à la théorie mathématique du jeu de billard'.")
