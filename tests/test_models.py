"""The model registry: each model's defaults live on its entry, and the analyses read them there.

``rocking.dynamics.models.MODELS`` holds per model the default rtol, the rest criterion and
the contact spring–dashpot; ``rocking.dynamics.names`` the names and the damped defaults
(written once; the schema, the configuration defaults and the help texts agree with them).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml

from rocking.cli import build_parser
from rocking.config.fields import DEFAULTS
from rocking.dynamics import analysis, models, names
from rocking.dynamics.bodies import Block, Cylinder
from rocking.spectra import modes

SCHEMA = yaml.safe_load((Path(__file__).parents[1]
                         / "workflow/schemas/config.schema.yaml").read_text())


def test_registry_is_keyed_by_the_model_names():
    assert tuple(models.MODELS) == names.MODEL_NAMES == ("3d", "3d-damped", "2d")
    assert all(m.name == name for name, m in models.MODELS.items())


def test_modes_run_registered_models_and_the_schema_lists_them():
    assert SCHEMA["definitions"]["mode"]["enum"] == list(modes.MODES)
    assert {mode.model for mode in modes.MODES.values()} == set(models.MODELS)
    # a spin at uplift exactly where the 3D model runs under one component
    assert [m for m, mode in modes.MODES.items() if mode.spin] == list(modes.UNIDIRECTIONAL_MODES)
    assert all(modes.MODES[m].model == names.MODEL_3D and modes.MODES[m].component
               for m in modes.UNIDIRECTIONAL_MODES)
    assert [m for m in modes.MODES if modes.is_damped(m)] == [modes.MODE_3D_DAMPED]
    # the damped mode and the damped model are distinct names that spell alike
    assert modes.MODES[modes.MODE_3D_DAMPED][0] == names.MODEL_3D_DAMPED


def test_only_the_damped_model_has_a_contact_whose_defaults_the_schema_states():
    assert [n for n, m in models.MODELS.items() if m.contact] == [names.MODEL_3D_DAMPED]
    props = SCHEMA["properties"]["damped"]["properties"]
    contact = models.MODELS[names.MODEL_3D_DAMPED].contact
    wn, z = contact.omega_n, contact.zeta
    assert (wn, z) == (props["omega_n"]["default"], props["zeta"]["default"]) == (2000.0, 5.0)
    assert DEFAULTS["damped"] == {"omega_n": wn, "zeta": z}
    assert (wn, z) in names.PAPER_CONTACT_GRID and len(set(names.PAPER_CONTACT_GRID)) == 8


@pytest.mark.parametrize("command", ["spectra", "stripes"])
def test_help_states_the_damped_defaults(command):
    sub = next(a for a in build_parser([command])._actions if a.dest == "command")
    text = " ".join(sub.choices[command].format_help().split())
    assert "frequency of mode 3d-damped [rad/s] (default: 2000)" in text
    assert "damping ratio of mode 3d-damped [-] (default: 5)" in text


def test_analysis_reads_rtol_and_rest_tilt_from_the_entry(monkeypatch):
    """Change an entry and the analyses' defaults follow (no copy elsewhere)."""
    body = Cylinder(2.0, 0.25)
    for name, m in models.MODELS.items():
        assert analysis._check_rtol(None, name) == m.rtol
        assert analysis.default_rest_tilt(name, body) == m.rest_tilt(body)
    for name in models.MODELS:
        entry = models.MODELS[name]
        monkeypatch.setitem(models.MODELS, name,
                            entry._replace(rtol=3e-7, rest_tilt=lambda b: 1e-9 * b.R))
        assert analysis._check_rtol(None, name) == 3e-7
        assert analysis.default_rest_tilt(name, body) == 2e-9


def test_rest_tilts_of_the_entries():
    """"3d": the tilt that lifts the rim of the base (diameter 2R sin α) by REST_LIFT,
    computed here from the geometry; the 2D and damped models a fixed tilt."""
    for R, tan_alpha in ((0.5, 0.2), (6.0, 0.15)):
        cyl = Cylinder(R, tan_alpha)
        alpha = math.atan(tan_alpha)
        theta = models.MODELS["3d"].rest_tilt(cyl)
        assert 2.0 * R * math.sin(alpha) * math.sin(theta) == pytest.approx(5e-6, rel=1e-9)
        assert models.MODELS["3d-damped"].rest_tilt(cyl) == 1e-6
        assert models.MODELS["2d"].rest_tilt(Block(R, tan_alpha)) == 0.0
