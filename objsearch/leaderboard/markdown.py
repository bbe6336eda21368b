"""Text for Markdown pages: a value as it must go into a table cell or heading to show as itself."""

from __future__ import annotations

import html
import re


def markdown_text(text) -> str:
    """``text`` as it must go into a Markdown table cell or heading to show as itself: HTML
    tags and entities escaped, line breaks as spaces, and the characters that end a cell or
    start markup (``\\ ` * [ ] |``) backslash-escaped."""
    text = html.escape(" ".join(str(text).splitlines()), quote=False)
    return re.sub(r"([\\`*\[\]|])", r"\\\1", text)
