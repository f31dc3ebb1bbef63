"""Griffe extension for the API pages: a numpy-docstring ``.. math::`` directive becomes a display
equation that MathJax renders (``$$ ... $$``, read by pymdownx.arithmatex), instead of the literal
text of an unknown reStructuredText directive. Loaded by mkdocs.yml (mkdocstrings ``extensions``)."""

from __future__ import annotations

import re

import griffe

_DIRECTIVE = re.compile(r"^(?P<indent>[ \t]*)\.\. math::[ \t]*(?P<first>.*)$")


def math_to_markdown(text: str) -> str:
    """Rewrite every ``.. math::`` block of ``text`` (the directive's own line and the lines
    indented deeper than it) as a ``$$ ... $$`` display block at the directive's indentation."""
    lines, out, i = text.splitlines(), [], 0
    while i < len(lines):
        m = _DIRECTIVE.match(lines[i])
        if m is None:
            out.append(lines[i])
            i += 1
            continue
        indent, body = m["indent"], [m["first"].strip()] if m["first"].strip() else []
        i += 1
        while i < len(lines) and (
            not lines[i].strip() or len(lines[i]) - len(lines[i].lstrip()) > len(indent)
        ):
            if lines[i].strip():
                body.append(lines[i].strip())
            elif (
                body and i + 1 < len(lines) and len(lines[i + 1]) - len(lines[i + 1].lstrip()) <= len(indent)
            ):
                break
            i += 1
        out += ["", f"{indent}$$", *(f"{indent}{b}" for b in body), f"{indent}$$", ""]
    return "\n".join(out)


class MathDirective(griffe.Extension):
    """Rewrite ``.. math::`` blocks in every docstring as it is loaded."""

    def on_instance(self, *, node, obj, agent, **kwargs) -> None:
        if obj.docstring is not None and ".. math::" in obj.docstring.value:
            obj.docstring.value = math_to_markdown(obj.docstring.value)
