"""Caption text shared by several figures. A figure's own caption is part of its entry
(``FIGURE.caption`` and ``FIGURE.paper`` in its module, :class:`.registry.FigureSpec`);
:func:`.registry.caption` composes it for a reproduction of the paper or a study of one's
own."""

from __future__ import annotations

UNRESOLVED = ("Answers flagged unresolved (the response came close to the goal below the "
              "answer, so a narrower window of exceedance may lie lower) are counted per curve "
              "in the legend.")
"""What the legend of a spectrum figure counts as unresolved."""
