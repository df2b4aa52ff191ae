"""Caption text shared by several figures. A figure's own caption is part of its entry
(``FIGURE.caption`` and ``FIGURE.paper`` in its module, :class:`.registry.FigureSpec`);
:func:`.registry.caption` composes it for a reproduction of the paper or a study of one's
own."""

from __future__ import annotations

QUANTITY = ("Each answer is the study's critical intensity: by default I10, the lowest "
            "PGA/(g tan α) near which at least 10 % of the intensities (within ±2 % in ln s) "
            "exceed the goal, a quantity that converges where the smallest exceeding intensity "
            "does not; the legend names it.")
"""What the answers of a spectrum figure are (docs/models.md, "The critical intensity")."""

PLATEAU = ("Answers flagged plateau (the share of exceeding intensities rises near 10 % below "
           "the answer without reaching it, so the answer is ill-conditioned there) are "
           "counted per curve in the legend.")
"""What the legend of a spectrum figure counts as on a plateau."""
