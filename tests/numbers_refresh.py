"""Rewrite the stale numbers of the README's and the docs' result links after their JSON sources were regenerated.

Every result number in the docs is a link to a committed JSON key (tests/numbers_checker.py). When the JSON files
under :data:`numbers_checker.SOURCES` are regenerated, the links whose text no longer shows their value are
rewritten here, in the format of the old text:

- a number value: the first number of the text (the one the checker reads) becomes the value rounded to the old
  text's decimals, times 100 before a ``%``, in minutes or hours before `` min`` / `` h``, with thousands commas
  where the old number had them or grew from under 10,000 to 10,000 or more (a long number written without, such
  as a seed, stays without), and the old sign character (``-``, ``−``, ``+``); everything else in the text (units,
  an ``x`` suffix, words) stays;
- a string value (``"10/10"``, ``"plastic 27/30, static 10/30"``): the text is matched against the string as a
  pattern, its numbers as wildcards and its other characters as they are (any run of spaces or line breaks as any
  other); where exactly one part of the string matches, the text's numbers become that part's numbers. Where no
  part or several parts match ("27/30" in "plastic 28/30, static 10/30"), the link is left as it is and reported.

Links to non-JSON targets, to whole files (no ``#key``), links in code or HTML comments and every number outside a
link's text are never touched. A text is stale where it does not show its value as :func:`shows_strictly` reads
it: the checker's :func:`numbers_checker.shows`, and for a string value each number of the text a whole number of
the string (the checker takes "10/10" for "9/10", its numbers being substrings). Each rewrite is checked the same
way before it is written.

Usage (from the repository root)::

    python tests/numbers_refresh.py                 # README.md and every docs page test_numbers.py checks
    python tests/numbers_refresh.py docs/performance.md --dry-run
    python tests/numbers_refresh.py --root /some/checkout

It prints one line per rewrite (``file:line: [old] -> [new]``), then the links it could not fix with the reason,
then a reminder to reread the prose around the rewritten links (a "faster" or "more than" may no longer hold). It
exits 1 when a link is left unfixed, 0 otherwise.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from numbers_checker import LINK, NUMBER, _number, lookup, prose, shows

ROOT = Path(__file__).resolve().parents[1]

#: A number inside a pattern built from a link text: a whole number of the string value, not a piece of one.
_WILDCARD = r"(" + NUMBER.pattern + r")(?!\d|[.,]\d)"
#: What :func:`numbers_checker.lookup` raises for a target whose file or key is not there.
LOOKUP_ERRORS = (KeyError, IndexError, ValueError, OSError, TypeError)

#: Resolves a link target to ``(value, "source#key")``, or None where the target is not a result source.
Resolver = Callable[[str], tuple[object, str] | None]


class UnfixableError(Exception):
    """A stale link text that cannot be rewritten; the message says why."""


@dataclass(frozen=True)
class Rewrite:
    """One link text rewritten: where it is, the old text, the new one, and the source it now shows."""

    line: int
    old: str
    new: str
    where: str
    value: object


@dataclass(frozen=True)
class Unfixed:
    """One link whose text does not show its source and that was left as it is, with the reason."""

    line: int
    text: str
    target: str
    why: str


def shows_strictly(text: str, value: object) -> bool:
    """Whether link text ``text`` shows ``value``: :func:`numbers_checker.shows`, and for a string value its numbers
    as whole numbers of the string, each as often as the text has it.

    The checker lets a text show a string when each of its numbers is a substring of the string, so "10/10" still
    passes for a value that became "9/10"; the refresher reads such a text as stale.
    """
    if not shows(text, value):
        return False
    if not isinstance(value, str) or text.strip() == value.strip():
        return True
    have = Counter(_number(m.group(0)) for m in NUMBER.finditer(value))
    return not Counter(_number(m.group(0)) for m in NUMBER.finditer(text)) - have


def mask(text: str) -> str:
    """``text`` with what :func:`numbers_checker.prose` drops (code, HTML comments, images) blanked to spaces.

    Unlike ``prose`` the result has the length of ``text`` (line breaks are kept), so a position in it is a
    position in ``text``: links are found in the mask and rewritten in the text.
    """

    def blank(m: re.Match[str]) -> str:
        return re.sub(r"[^\n]", " ", m.group(0))

    text = re.sub(r"```.*?```", blank, text, flags=re.S)
    text = re.sub(r"<!--.*?-->", blank, text, flags=re.S)
    text = re.sub(r"`(?:[^`\n]|\n(?![ \t]*\n))*`", blank, text)
    return re.sub(r"!\[[^\]]*\]\([^)]*\)", blank, text)


def render(old: str, x: float) -> str:
    """``x`` written as the number ``old`` was: its decimals, its thousands commas, its sign character."""
    digits = len(old.split(".")[1]) if "." in old else 0
    r = round(x, digits)
    # the old commas; a number that grew to 10,000 or more gets them (one of 10,000 or more written without, a
    # seed such as 1000000000, stays without)
    commas = "," in old or (abs(r) >= 10000 and abs(float(old.replace("−", "-"))) < 10000)
    body = f"{abs(r):,.{digits}f}" if commas else f"{abs(r):.{digits}f}"
    if r < 0 and float(body.replace(",", "")) != 0:
        return (old[0] if old[0] in "-−" else "-") + body
    return ("+" if old[0] == "+" else "") + body


def refresh_number(text: str, masked: str, value: float) -> str:
    """``text`` (a link text; ``masked``: the same without its inline code) with its first number showing ``value``.

    The first number is the one :func:`numbers_checker.shows` reads; a ``%`` right after it makes the value a share
    (shown times 100), `` min`` or `` h`` a time in seconds (shown in minutes or hours).
    """
    if not math.isfinite(value):
        raise UnfixableError(f"the value {value!r} is not a finite number")
    m = NUMBER.search(masked)
    if m is None:
        raise UnfixableError("the text has no number to show the value with")
    x = float(value) * (100.0 if masked[m.end() : m.end() + 1] == "%" else 1.0)
    scale = {" min": 60.0, " h": 3600.0}.get(masked[m.end() : m.end() + 4].rstrip(), 1.0)
    return text[: m.start()] + render(m.group(0), x / scale) + text[m.end() :]


def _pattern(text: str, numbers: Sequence[re.Match[str]]) -> str:
    """A regex for the parts of a string that read as ``text``: its numbers any numbers, its spacing any spacing."""

    def literal(piece: str) -> str:
        return r"\s+".join(re.escape(p) for p in re.split(r"\s+", piece))

    parts, at = [], 0
    for m in numbers:
        parts += [literal(text[at : m.start()]), _WILDCARD]
        at = m.end()
    return "".join([*parts, literal(text[at:])])


def refresh_string(text: str, masked: str, value: str) -> str:
    """``text`` (a link text showing the whole string ``value`` or a part of it) with the numbers of that part now.

    Raises :class:`UnfixableError` where the text matches no part of ``value`` or several parts with different numbers.
    """
    numbers = list(NUMBER.finditer(masked))
    if not numbers:
        raise UnfixableError("the text has no number to rewrite")
    # every part, overlapping ones too (a lookahead), by its numbers (group 1 is the whole part)
    found = {m.groups()[1:] for m in re.finditer(f"(?=({_pattern(text, numbers)}))", value)}
    if not found:
        raise UnfixableError(f"the text matches no part of the string {value!r}")
    if len(found) > 1:
        raise UnfixableError(f"the text matches {len(found)} parts of the string {value!r}: ambiguous")
    (new,) = found
    out, at = [], 0
    for m, number in zip(numbers, new, strict=True):
        out += [text[at : m.start()], number]
        at = m.end()
    return "".join([*out, text[at:]])


def refresh_link(text: str, value: object, masked: str | None = None) -> str:
    """The link text ``text`` rewritten to show ``value`` in its own format (``masked``: ``text`` less its code).

    Raises :class:`UnfixableError` where it cannot be, or where the checker would not accept the rewrite.
    """
    masked = mask(text) if masked is None else masked
    if isinstance(value, str):
        new = refresh_string(text, masked, value)
    elif isinstance(value, int | float) and not isinstance(value, bool):
        new = refresh_number(text, masked, value)
    else:
        raise UnfixableError(f"the value {value!r} is not a number or a string")
    if not shows_strictly(prose(new), value):
        raise UnfixableError(f"the checker does not accept the rewrite {new!r}")
    return new


def refresh_text(text: str, resolve: Resolver) -> tuple[str, list[Rewrite], list[Unfixed]]:
    """``text`` (a markdown page) with every stale link text to a JSON source key rewritten, the rewrites, and the
    links left as they were.

    ``resolve`` maps a link target to ``(value, "source#key")``, or to None where the target is not a result
    source (other files, web pages), and raises one of :data:`LOOKUP_ERRORS` where the file or key is missing.
    """
    masked = mask(text)
    edits: list[tuple[int, int, str]] = []
    rewrites: list[Rewrite] = []
    unfixed: list[Unfixed] = []
    for m in LINK.finditer(masked):
        target, old = m.group(2), text[m.start(1) : m.end(1)]
        line = text.count("\n", 0, m.start()) + 1
        try:
            got = resolve(target)
        except LOOKUP_ERRORS as e:
            unfixed.append(Unfixed(line, old, target, f"no such source ({type(e).__name__}: {e})"))
            continue
        if got is None or not got[1].partition("#")[2]:  # not a source, or a whole file (its name, no value)
            continue
        value, where = got
        if shows_strictly(prose(old), value):
            continue
        try:
            new = refresh_link(old, value, masked[m.start(1) : m.end(1)])
        except UnfixableError as e:
            unfixed.append(Unfixed(line, old, target, f"{where} = {value!r}: {e}"))
            continue
        edits.append((m.start(1), m.end(1), new))
        rewrites.append(Rewrite(line, old, new, where, value))
    for start, end, new in reversed(edits):
        text = text[:start] + new + text[end:]
    return text, rewrites, unfixed


def refresh_file(root: Path, doc: Path, write: bool = True) -> tuple[list[Rewrite], list[Unfixed]]:
    """Refresh the page ``doc`` of the checkout ``root`` in place (unless not ``write``); its rewrites and leftovers."""
    text = doc.read_text(encoding="utf-8")
    new, rewrites, unfixed = refresh_text(text, lambda target: lookup(root, doc, target))
    if write and new != text:
        doc.write_text(new, encoding="utf-8")
    return rewrites, unfixed


def default_pages(root: Path) -> list[Path]:
    """The pages tests/test_numbers.py checks in ``root``: README.md and docs/**/*.md but the generated ones."""
    from test_numbers import GENERATED, RESULTS

    docs = sorted(p.relative_to(root).as_posix() for p in (root / "docs").rglob("*.md"))
    pages = ["README.md", *(p for p in docs if not p.startswith(RESULTS) and p not in GENERATED)]
    return [root / p for p in pages if (root / p).is_file()]


def _one_line(text: str) -> str:
    return " ".join(text.split())


def main(argv: Sequence[str] | None = None) -> int:
    """Refresh the pages named on the command line (default: :func:`default_pages`); 1 if a link is left unfixed."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("files", nargs="*", type=Path, help="markdown pages (default: README.md and the docs)")
    parser.add_argument("--root", type=Path, default=ROOT, help="the checkout the sources are read from")
    parser.add_argument("--dry-run", action="store_true", help="report the rewrites without writing them")
    args = parser.parse_args(argv)
    root = args.root.resolve()
    docs = [(f if f.exists() else root / f).resolve() for f in args.files] or default_pages(root)

    changed: list[str] = []
    left: list[str] = []
    count = 0
    for doc in docs:
        name = doc.relative_to(root).as_posix() if doc.is_relative_to(root) else str(doc)
        rewrites, unfixed = refresh_file(root, doc, write=not args.dry_run)
        for r in rewrites:
            print(f"{name}:{r.line}: [{_one_line(r.old)}] -> [{_one_line(r.new)}]  ({r.where} = {r.value!r})")
        left += [f"{name}:{u.line}: [{_one_line(u.text)}]({u.target}): {u.why}" for u in unfixed]
        count += len(rewrites)
        if rewrites:
            changed.append(name)
    verb = "to rewrite" if args.dry_run else "rewritten"
    print(f"{count} link text(s) {verb} in {len(changed)} file(s), {len(left)} left unfixed")
    if left:
        print("Not fixed:")
        print("\n".join(f"  {line}" for line in left))
    if changed:
        print(
            "Reminder: reread the prose around the rewritten links for comparisons that may no longer hold "
            f"('faster', 'more than', 'all', ...): {', '.join(changed)}"
        )
    return 1 if left else 0


if __name__ == "__main__":
    sys.exit(main())
