"""The ``resal`` typer app, on which each command module registers its command, and the one-line usage errors of
every command: an unknown option or command, a missing argument, a value click refused."""

from __future__ import annotations

from typing import Annotated, Any

import typer

from cli.common import _fail
from reproductions.errors import InputError, did_you_mean


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
        return InputError(f"command '{name}'", f"not a command of `{path}`{did_you_mean(name, ctx.command.commands)}"
                                               f" (expected one of {', '.join(ctx.command.commands)}; see {path} "
                                               "--help)")
    where = getattr(exc, "option_name", None) or path  # an option given without its value: the option
    return InputError(where, f"{exc.format_message()} (see {path} --help)")  # type: ignore[attr-defined]


def _summary(help_text: str) -> str:
    """A command's line in its group's list of commands: the first paragraph of its help, whole (click would cut
    it at its first period or at the width left, "§I eq." or "write tables...")."""
    first = help_text.strip().split("\n\n", 1)[0]
    return " ".join(w for w in first.split() if w != "\b")


def _plain_arguments(cmd: Any) -> Any:
    """The arguments of ``cmd`` named in capitals in its usage line, help and errors, as POSIX usage lines and
    click write them (``resal diff [OPTIONS] A B``, not typer's ``{a} {b}``): an optional one in brackets, one
    that repeats followed by ``...``."""
    import types

    def pieces(self: Any, ctx: Any) -> list[str]:
        name = self.metavar if self.required else f"[{self.metavar}]"
        return [name + ("..." if self.nargs != 1 else "")]

    for p in getattr(cmd, "params", ()):
        if p.param_type_name == "argument" and not getattr(p, "_plain", False):
            p.metavar = p.metavar or p.name.upper()
            p.get_usage_pieces = types.MethodType(pieces, p)
            p._plain = True
    return cmd


class _OneLineGroup(typer.core.TyperGroup):
    """Every usage mistake gets one ``error:`` line and exit 2, as all bad input does, never click's usage screen:
    the group's own options, its command names, and (around each command it runs) the command's own arguments; so
    every command of the app, the ones added later too, behaves the same. Its commands' help lists each by the
    first paragraph of its help, whole; their arguments read in capitals (``_plain_arguments``)."""

    def get_command(self, ctx: Any, cmd_name: str) -> Any:
        return _plain_arguments(super().get_command(ctx, cmd_name))

    def format_commands(self, ctx: Any, formatter: Any) -> None:
        rows = []
        for name in self.list_commands(ctx):
            cmd = self.get_command(ctx, name)
            if cmd is not None and not cmd.hidden:
                rows.append((name, cmd.short_help or _summary(cmd.help or "")))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)

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
                  rich_markup_mode=None)


def _version(value: bool) -> None:
    """``resal --version``: resal's version, its git commit when it runs from a checkout (as summary.json's
    provenance records it), and the versions of Python, numpy and scipy; one line each, then exit 0."""
    if not value:
        return
    from reproductions.report import code_provenance

    c = code_provenance()
    lines = [f"resal {c['version']}"]
    if c["git_commit"]:
        lines.append(f"commit {c['git_commit'][:12]}" + (" (with uncommitted changes)" if c["dirty"] else ""))
    lines += [f"Python {c['python']}", *(f"{m} {c[m] or 'not installed'}" for m in ("numpy", "scipy"))]
    typer.echo("\n".join(lines))
    raise typer.Exit(0)


@app.callback()
def _resal(version: Annotated[bool, typer.Option(
        "--version", is_eager=True, callback=_version,
        help="print the versions of resal (and its git commit), Python, numpy and scipy, and exit")] = False) -> None:
    """Reproduce H. Résal (1883), 'Commentaire à la théorie mathématique du jeu de billard'.

    \b
    Examples:
      resal list
      resal reproduce coriolis-pendulum
      resal reproduce --all
      resal simulate wall-impact --set eps=0.3
      resal examples
      resal fit rebound resal-examples/rebound.csv

    Each command's --help gives its own examples: resal reproduce --help.
    """
