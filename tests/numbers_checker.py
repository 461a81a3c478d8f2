"""Where every number in the README and docs comes from: the checker behind tests/test_numbers.py.

A number that is a result is written as a link to its source, a committed JSON result file (:data:`SOURCES`):
docs/results/ (`neurowalk reproduce`), docs/benchmarks/ (`neurowalk bench`, benchmarks/), docs/baselines/
(`neurowalk baseline`) or docs/optimize/ (`neurowalk optimize`), with the key path after ``#`` (keys joined by
``/``, list items by index, a space in a key written ``%20``: the path is URL-decoded key by key):

    the plastic network escaped [10/10](docs/results/fig8.json#claims/0/measured) of the narrow passages

The link's text must show the value at that key: the same string, or the same number as rounded in the text (a
``%`` after it: the value is a share, shown times 100; `` min`` or `` h`` after it: the value is in seconds; ``e-7``
after it: the mantissa as rounded, times that power of ten). A
string value holding several numbers (a rule, a command) backs the numbers of the text that it holds as whole
numbers, each as often as the text shows it (a text of words alone: words the string holds). A link
to a whole source file (no ``#key``) names the file and states nothing: its text is prose, where a number that
is not a name is flagged. Every other number in the prose must be one that states no result: a figure, table,
equation or section number (also with "Fig." or "Table" at the end of one line and the number at the start of
the next), a year (also followed by a comma or other punctuation), a version, a count of the paper's model
(:data:`WORDS`), or inside code (a command, a path, a setting such as `seed 0`), which the checker leaves alone.
"""

from __future__ import annotations

import json
import re
from collections import Counter
from pathlib import Path
from urllib.parse import unquote

#: The committed result files: `neurowalk reproduce`'s run, `neurowalk bench`'s, the two studies' (`neurowalk
#: baseline`, `neurowalk optimize`).
SOURCES = ("docs/results/", "docs/benchmarks/", "docs/baselines/", "docs/optimize/", "docs/studies/")
#: A number: digits with thousands commas and a decimal part; a comma after it (a year in "2014,") is not its own.
NUMBER = re.compile(r"(?<![\w.])[-+−]?\d(?:[\d,]*\d)?(?:\.\d+)?")
LINK = re.compile(r"\[([^\]]*)\]\(([^)\s]+)\)")
#: Text before a number that makes it a name, not a result: "Fig. 8", "Table 2", "§2.2", "Eq. 3", "issue 28", and
#: the end of a range of such names: "Eq. 1-6", "Fig. 3-5".
NAMING = re.compile(
    r"(?:Fig(?:ure|s)?\.?|Tables?|§|Eqs?\.|Equations?|issues?|sections?|Python|panels?|step|Video|"
    r"Supplementary\s+Video)\s*(?:\d+[-–])?$",
    re.IGNORECASE,
)
#: Numbers of the paper's model and of the robot that the text names (not results): counts of parts. AMOSII's 19
#: joints (its 19 DOF) are named as such too: "the 19 joint targets", "AMOSII's 19 actuator names"; "3-D" is a word.
WORDS = re.compile(r"^(?:3-D|19-DOF|19 DOF|19 (?:joint|actuator)|two-neuron|\d+-neuron)")
YEAR = re.compile(r"^(?:19|20)\d\d$")


def prose(text: str) -> str:
    """``text`` without code fences, inline code, HTML comments and images (their numbers are not claims)."""
    text = re.sub(r"```.*?```", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    text = re.sub(r"<!--.*?-->", "", text, flags=re.S)
    # inline code, which may wrap onto the next line of its paragraph (not across a blank line); its lines are kept
    text = re.sub(r"`(?:[^`\n]|\n(?![ \t]*\n))*`", lambda m: "``" + "\n" * m.group(0).count("\n"), text)
    return re.sub(r"!\[[^\]]*\]\([^)]*\)", "", text)


def lookup(root: Path, doc: Path, target: str) -> tuple[object, str] | None:
    """The value a link ``target`` names and the source it reads, or None where the target is not a source."""
    file, _, key = target.partition("#")
    path = (doc.parent / file).resolve()
    rel = path.relative_to(root.resolve()).as_posix() if path.is_relative_to(root.resolve()) else ""
    if not rel.startswith(SOURCES) or not rel.endswith(".json"):
        return None
    value: object = json.loads(path.read_text(encoding="utf-8"))
    for part in (unquote(k) for k in key.split("/")) if key else []:
        if isinstance(value, list):
            value = value[int(part)]
        elif isinstance(value, dict):
            value = value[part]
        else:
            raise KeyError(part)
    return value, f"{rel}#{key}"


def _number(text: str) -> float:
    return float(text.replace(",", "").replace("−", "-"))


def shows(text: str, value: object) -> bool:
    """Whether link text ``text`` shows ``value`` (see the module doc)."""
    if isinstance(value, str):  # each number of the text a whole number of the string, as often as the text has it
        if text.strip() == value.strip():
            return True
        have = Counter(_number(n.group(0)) for n in NUMBER.finditer(value))
        want = Counter(_number(n.group(0)) for n in NUMBER.finditer(text))
        return not want - have if want else text.strip() in value  # no number: the words, as in the string
    if isinstance(value, bool) or not isinstance(value, int | float):
        return False
    m = NUMBER.search(text)
    if m is None:
        return False
    shown = m.group(0)
    power = re.match(r"e([-+−]?\d+)", text[m.end() :])  # 4.77e-7: the mantissa as rounded, times its power of ten
    if power:
        exponent = int(power.group(1).replace("−", "-"))
        digits = len(shown.split(".")[1]) if "." in shown else 0
        return round(float(value) / 10.0**exponent, digits) == _number(shown)
    x = float(value) * (100.0 if text[m.end() : m.end() + 1] == "%" else 1.0)
    digits = len(shown.split(".")[1]) if "." in shown else 0
    scale = {" min": 60.0, " h": 3600.0}.get(text[m.end() : m.end() + 4].rstrip(), 1.0)
    return round(x / scale, digits) == _number(shown)


def problems(root: Path, doc: Path) -> list[str]:
    """Every number of ``doc`` (a markdown file under ``root``) that differs from its source or has none."""
    found = []
    text = prose(doc.read_text(encoding="utf-8"))
    spans, files = [], []
    for m in LINK.finditer(text):
        spans.append((m.start(2) - 2, m.end(2) + 1))  # the target's own numbers are not claims
        try:
            got = lookup(root, doc, m.group(2))
        except (KeyError, IndexError, ValueError, OSError) as e:
            spans.append((m.start(1), m.end(1)))
            found.append(f"{doc.name}: [{m.group(1)}]({m.group(2)}): no such source ({type(e).__name__}: {e})")
            continue
        if got is not None:
            value, where = got
            if not where.partition("#")[2]:  # the whole file: its name, no claim; its text is prose
                files.append((m.start(1), m.end(1)))
                continue
            spans.append((m.start(1), m.end(1)))
            if not shows(m.group(1), value):
                found.append(f"{doc.name}: {m.group(1)!r} differs from its source {where} = {value!r}")
    for m in NUMBER.finditer(text):
        if any(a <= m.start() < b for a, b in spans):
            continue
        line_start = text.rfind("\n", 0, m.start()) + 1
        before, after = text[line_start : m.start()], text[m.start() : m.start() + 12]
        if not before.strip():  # "Fig." at the end of the line before, its number starting this one
            before = text[text.rfind("\n", 0, max(line_start - 1, 0)) + 1 : m.start()]
        if text[line_start:].startswith("#") or NAMING.search(before) or YEAR.match(m.group(0)):
            continue
        if WORDS.match(after) or re.match(r"\d+\.\d+\.\d+", after):
            continue
        lineno = text.count("\n", 0, m.start()) + 1
        whole = " (a link to a whole file: a value needs its #key)" if any(a <= m.start() < b for a, b in files) else ""
        found.append(f"{doc.name}:{lineno}: {m.group(0)!r} has no source{whole} ({before[-40:]}{after})")
    return found
