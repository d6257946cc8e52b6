"""The two kinds of check and how they are run.

Figure(readme, text, value): `text` is the exact text the README quotes, with a str.format field ({:.3f},
{:+.1%}, {}) where each figure stands; `value` a function that recomputes the figure(s) from committed CSV rows
(rows.py). The check formats the recomputed value(s) into `text` and requires the README to hold the result
(whitespace and line breaks collapsed, a leading '-' of a number written '−' unless minus='-'). A figure that
was edited, or that the rows round differently, is a failure naming the README, the text it quotes and the
recomputed value.

Unrecorded(readme, text, source): figures the README quotes that no committed file holds (a wall time written down
from the console, a table a script printed from files it did not keep): the check only requires the README to hold
`text` and to name `source`; the coverage line counts these figures apart, as quoted without a committed source.

Generated(output, command): a Markdown (or CSV) file written by a script from committed rows. The command runs
again into a temporary folder and its output must equal the committed file (mode 'lines': every committed line
that holds a digit must be in the new output, for a file an earlier version of the script wrote).
"""
import os
import re
import shutil
import string
import subprocess
import tempfile

from results_checks.rows import ROOT

_FORMATTER = string.Formatter()


def squash(text):
    return re.sub(r"\s+", " ", text)


def render(template, values, minus="−"):
    """`template` with each {spec} field replaced by the next value, formatted by spec."""
    if not isinstance(values, (tuple, list)):
        values = (values,)
    out, i = [], 0
    for literal, name, spec, _ in _FORMATTER.parse(template):
        out.append(literal)
        if name is None:
            continue
        value = values[i]
        i += 1
        text = format(value, spec or "") if not isinstance(value, str) else value
        if minus != "-" and text.startswith("-"):
            text = minus + text[1:]
        out.append(text)
    if i != len(values):
        raise ValueError(f"{len(values)} values for {i} fields in {template!r}")
    return "".join(out)


def pattern(template):
    """A regex that finds `template` with any figure in place of its fields (to show what the README says)."""
    out = []
    for literal, name, _, _ in _FORMATTER.parse(template):
        out.append(re.escape(squash(literal)).replace(r"\ ", r"\s"))
        if name is not None:
            out.append(r"[−+\-]?[\w.,]*%?")
    return "".join(out)


class Figure:
    def __init__(self, readme, text, value, minus="−"):
        self.readme, self.text, self.value, self.minus = readme, squash(text), value, minus

    def describe(self):
        return f"{self.readme}: {self.text!r}"

    def expected(self):
        return render(self.text, self.value(), self.minus)

    def run(self, read):
        """None when the README holds the recomputed text, else one line saying what differs."""
        try:
            values = self.value()
            want = render(self.text, values, self.minus)
        except Exception as e:  # a check that cannot compute is a failure too
            return f"{self.readme}: {self.text!r}: cannot recompute: {type(e).__name__}: {e}"
        have = squash(read(self.readme))
        if want in have:
            return None
        found = re.search(pattern(self.text), have)
        said = f"the README says {found.group(0)!r}" if found else "the text is not in the README"
        shown = ", ".join(f"{v:.6g}" if isinstance(v, float) else str(v)
                          for v in (values if isinstance(values, (tuple, list)) else (values,)))
        return f"{self.readme}: expected {want!r} (recomputed {shown}); {said}"


class Unrecorded(Figure):
    """`text`: the README's words with their figures (no format fields); `source`: words the README uses to say
    where the figures come from (the check fails when the README no longer says it)."""

    def __init__(self, readme, text, source):
        super().__init__(readme, text, tuple, "-")
        self.source = squash(source)

    def run(self, read):
        have = squash(read(self.readme))
        if self.text not in have:
            return f"{self.readme}: {self.text!r} (recorded in no committed file) is not in the README"
        if self.source not in have:
            return f"{self.readme}: the README no longer names the source of {self.text!r}: {self.source!r}"
        return None


class Generated:
    """`command`: the script and its arguments, relative to `cwd` (under the root); '{tmp}' stands for the
    temporary folder. `produced`: the file the command writes under {tmp}, or None for its standard output.
    `copy`: folders copied into {tmp} first (a script that writes beside its inputs)."""

    def __init__(self, output, command, cwd=".", produced=None, copy=(), mode="equal",
                 python="/usr/bin/python3"):
        self.readme, self.output, self.command, self.cwd = output, output, command, cwd
        self.produced, self.copy, self.mode, self.python = produced, copy, mode, python

    def describe(self):
        return f"{self.output}: regenerated by {' '.join(self.command)}"

    def regenerate(self):
        with tempfile.TemporaryDirectory() as tmp:
            for folder in self.copy:
                shutil.copytree(ROOT / folder, os.path.join(tmp, os.path.basename(folder)))
            args = [a.replace("{tmp}", tmp) for a in self.command]
            if args[0].endswith(".py"):
                args = [self.python, str(ROOT / args[0])] + args[1:]
            env = dict(os.environ, MPLBACKEND="Agg", LC_ALL="C")
            done = subprocess.run(args, cwd=ROOT / self.cwd, capture_output=True, text=True, env=env)
            if done.returncode != 0:
                raise RuntimeError(f"exit {done.returncode}: {done.stderr.strip()[-300:]}")
            if self.produced is None:
                return done.stdout
            with open(os.path.join(tmp, self.produced)) as f:
                return f.read()

    def run(self, read):
        try:
            new = self.regenerate()
        except Exception as e:
            return f"{self.output}: cannot regenerate ({' '.join(self.command)}): {e}"
        old = read(self.output)
        if self.mode == "lines":
            fresh = set(new.splitlines())
            missing = [line for line in old.splitlines() if re.search(r"\d", line) and line not in fresh]
        else:
            missing = [] if new == old else [a for a, b in zip(old.splitlines() + [""], new.splitlines() + [""])
                                             if a != b][:1] or ["(length differs)"]
        if not missing:
            return None
        return (f"{self.output}: differs from `{' '.join(self.command)}` on its rows, first at {missing[0][:120]!r}")


def read_file(path):
    with open(ROOT / path, encoding="utf-8") as f:
        return f.read()


class Embedded(Figure):
    """A table copied into a README from a generated file (which a Generated check makes again from its rows):
    the README's table lines after the line holding `after`, up to the first line that is not part of the table,
    must each be a line of `source`. Counted and self-tested as figures, one per table line."""

    def __init__(self, readme, source, after, prefix="|"):
        super().__init__(readme, "{}", self.lines, "-")
        self.source, self.after, self.prefix = source, after, prefix

    def lines(self):
        """The README's lines after the one holding `after` that start with `prefix` (a table's '|', a list's
        '- '), up to the first line that does not."""
        text = read_file(self.readme).splitlines()
        start = next(i for i, line in enumerate(text) if self.after in line)
        table = []
        for line in text[start + 1:]:
            if table and not line.startswith(self.prefix):
                break
            if line.startswith(self.prefix):
                table.append(line)
        return table

    def expected(self):
        return "\n".join(self.lines())

    def run(self, read):
        source = set(read_file(self.source).splitlines())
        readme = read(self.readme)
        for line in self.lines():
            if squash(line) not in squash(readme):
                return f"{self.readme}: the table line {line[:100]!r} is gone"
            if line not in source:
                return f"{self.readme}: the table line {line[:100]!r} is not in {self.source}"
        return None
