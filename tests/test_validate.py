"""The one check of a positive number (rocking._validate.positive_finite): its one-line
message names the key and the value, and no other module defines a check of its own."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import numpy as np
import pytest

from rocking._validate import positive_finite

SRC = Path(__file__).resolve().parents[1] / "src" / "rocking"


@pytest.mark.parametrize("value", [0, -1.0, math.nan, math.inf, -math.inf, True, None, "x",
                                   [1.0]])
def test_what_is_not_a_positive_number_is_refused_in_one_line_naming_key_and_value(value):
    with pytest.raises(ValueError) as err:
        positive_finite("studies.s.mu", value)
    assert str(err.value) == f"studies.s.mu must be a finite number > 0, got {value!r}"


def test_a_positive_number_is_returned_as_a_float():
    assert positive_finite("R", 2) == 2.0 and isinstance(positive_finite("R", 2), float)
    assert positive_finite("dt", np.float64(0.01)) == 0.01
    assert positive_finite("investigation_time", "50") == 50.0   # a field of a file
    assert positive_finite("tiny", 5e-324) == 5e-324


def test_no_module_defines_a_check_of_a_positive_number_of_its_own():
    """The five checks the house once had (``positive_field`` of the configuration,
    ``_positive`` of the hazard reader, the accuracy's range check asked for (0, ∞), the
    command line's inline checks) are this one: no function named for it elsewhere."""
    own = []
    for path in SRC.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.FunctionDef) and "positive" in node.name and \
                    path.name != "_validate.py":
                own.append(f"{path.relative_to(SRC)}:{node.name}")
    assert own == []


def test_an_array_of_positive_numbers_names_its_first_bad_value():
    from rocking._validate import positive_finite_array

    assert positive_finite_array("k", 2.0).ndim == 0  # a scalar stays one
    assert positive_finite_array("omega", [1.0, 2.0]).tolist() == [1.0, 2.0]
    for bad, told in (([1.0, 0.0, -1.0], "0.0 at sample 1"), ([np.nan], "nan at sample 0"),
                      (-3.0, "-3.0")):
        with pytest.raises(ValueError) as err:
            positive_finite_array("omega", bad)
        assert str(err.value) == f"omega must hold finite numbers > 0, got {told}"
