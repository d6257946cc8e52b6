"""Which numeric figures of the hand-written results documents no check covers (a warning list, not a failure).

A figure here is a decimal number (1.246), or a whole number followed by % or × (15%, 2×), in prose or a table:
code blocks (indented four spaces or fenced) and `inline code` are commands and names, not figures; a band written
±N% ('within ±15%') is the tolerance a count is taken against, not a measured figure (the count is); a percentage
that names a confidence level or a test's nominal rate ('the 95% interval', 'the 95% band', 'a 5% false-alarm
rate', 'the nominal 5%') is the test's setting, not a result; a number written right after × is the second side of
a size or tile (640×480, 32×8), not a ratio; in a section that documents a command or a file (its heading names it in `code`:
"## `raycoh quality` CSV") a figure written after =, <, >, ≤, ≥ or + is a constant of a definition ('σ = 1.5',
'|z| < 1.96', 'busy ≥ 80%', '(r² + 0.01)'), not a result. A figure is covered when it lies inside the text a Figure
check quotes, or the README has no figure outside such text.
"""
import re

from results_checks.core import squash

FIGURE = re.compile(r"(?<![\w.\-/×])[−+\-]?\d[\d,]*(?:\.\d+(?![.\d])|\s?[%×](?! ?\d))")
DEFINITION = re.compile(r"((?:[=<>≤≥]|\s\+)\s?)\d[\d,]*(?:\.\d+(?![.\d])|\s?[%×](?! ?\d))")
VERSION = re.compile(r"\b(?:CUDA|nvcc|driver|version|Embree|GPGPU-Sim|Denoise|clang-format|g\+\+|Python) [\d.]+")


def prose(text):
    """The README without code blocks and inline code, whitespace collapsed."""
    lines, fenced, format_section = [], False, False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if fenced or line.startswith("    "):
            continue
        if line.startswith("#"):
            format_section = "`" in line
        elif format_section:
            line = DEFINITION.sub(lambda m: m.group(1) + "N", line)
        lines.append(line)
    return squash(VERSION.sub(" ", re.sub(r"`[^`]*`", " ", "\n".join(lines))))


def uncovered(text, quoted):
    """The figures of `text` outside every one of the `quoted` texts (already rendered)."""
    body = prose(text)
    spans = []
    for q in quoted:
        q = squash(re.sub(r"`[^`]*`", " ", q)).strip()
        for form in {q, DEFINITION.sub(lambda m: m.group(1) + "N", q)}:  # as written, or in a format section
            start = body.find(form)
            while start >= 0:
                spans.append((start, start + len(form)))
                start = body.find(form, start + 1)
    return [m.group(0) for m in FIGURE.finditer(body)
            if not any(a <= m.start() and m.end() <= b for a, b in spans) and not band(body, m) and not level(body, m)]


def band(body, m):
    """A whole-number percentage written ±N%: a tolerance band."""
    return m.start() > 0 and body[m.start() - 1] == "±" and re.fullmatch(r"\d+%", m.group(0)) is not None


LEVEL = re.compile(r"\s(?:confidence|intervals?|tests?|bands?|false-alarm|CI)\b")


def level(body, m):
    """A whole-number percentage that names a confidence level or a test's rate: 'the 95% interval', 'a 95% test',
    'the 95% band', 'a 5% false-alarm rate'; or a percentage written right after the word 'nominal' (a test's
    nominal rate that a measured share is compared with: 'more than the nominal 5% of pixels', 'a nominal 2.5%')."""
    whole = re.fullmatch(r"\d+%", m.group(0)) is not None
    if whole and LEVEL.match(body, m.end()) is not None:
        return True
    percent = whole or (re.fullmatch(r"\d+\.\d+", m.group(0)) is not None and body.startswith("%", m.end()))
    return percent and body[:m.start()].endswith("nominal ")
