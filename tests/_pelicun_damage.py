"""pelicun's damage calculation on one asset of a rocking exposure export; prints JSON.

Run by tests/test_exposure.py with an interpreter that has pelicun 3 (its own, or the one
named by ``ROCKING_PELICUN_PYTHON``: pelicun 3.10 needs scipy < 1.16 and pandas < 3, which
the project's environment may not have). Usage::

    python _pelicun_damage.py FOLDER ASSET_ID PGA_G N

Prints the component, pelicun's medians in its internal unit (m/s²) and, per damage state
i, the share of the N realisations at damage state ≥ i under the constant demand PGA_G [g].
"""

import json
import sys

import pandas as pd
from pelicun.assessment import Assessment

folder, asset, pga, n = sys.argv[1], sys.argv[2], float(sys.argv[3]), int(sys.argv[4])
assets = pd.read_csv(f"{folder}/pelicun/assets.csv", index_col="id", dtype={"id": str})
row = assets.loc[asset]
asmnt = Assessment({"PrintLog": False, "Seed": 7, "Verbose": False})
asmnt.stories = 1
asmnt.demand.load_sample(pd.DataFrame({"PGA-1-1": ["g"] + [pga] * n},
                                      index=["Units", *range(n)]))
asmnt.asset.load_cmp_model(f"{folder}/pelicun/{row['marginals'].removesuffix('_marginals.csv')}")
asmnt.asset.generate_cmp_sample(n)
asmnt.damage.load_model_parameters([f"{folder}/pelicun/damage_model.csv"], {row["component"]})
params = asmnt.damage.ds_model.damage_params.loc[row["component"]]
asmnt.damage.calculate()
sample = asmnt.damage.ds_model.sample
ds = sample.columns.get_level_values("ds").astype(int)
states = sorted({int(c[2:]) for c, _ in params.index if c.startswith("LS")
                 and not pd.isna(params[(c, "Theta_0")])})
print(json.dumps({
    "component": row["component"],
    "theta_0_si": [float(params[(f"LS{i}", "Theta_0")]) for i in states],
    "theta_1": [float(params[(f"LS{i}", "Theta_1")]) for i in states],
    "p_ds_ge": [float(sample.loc[:, ds >= i].sum(axis=1).mean()) for i in states]}))
