"""OpenQuake's scenario_damage calculator on a rocking exposure export; prints JSON.

Run by tests/test_exposure.py in a subprocess whose HOME is a temporary folder (the engine
keeps its database and datastores under ``~/oqdata``). Usage::

    python _openquake_damage.py FOLDER PGA_G [PGA_G ...]

Writes ``sites.csv`` (the assets' positions), ``gmf.csv`` (the given PGA [g] at every site,
one event each) and ``job.ini`` into FOLDER beside ``exposure.xml`` and ``fragility.xml``,
runs the calculation in this process and prints, per asset id in the order of
``exposure.csv``, the engine's mean number of assets in each damage state (no damage first)
and per event the total.
"""

import json
import sys
from pathlib import Path

import pandas as pd
from openquake.calculators import base
from openquake.commonlib import logs

folder = Path(sys.argv[1])
pgas = [float(x) for x in sys.argv[2:]]
assets = pd.read_csv(folder / "exposure.csv", dtype={"id": str})
sites = assets[["lon", "lat"]].drop_duplicates().reset_index(drop=True)
sites.insert(0, "site_id", range(len(sites)))
sites.to_csv(folder / "sites.csv", index=False)
pd.DataFrame([{"site_id": s, "event_id": e, "gmv_PGA": pga} for e, pga in enumerate(pgas)
              for s in sites["site_id"]]).to_csv(folder / "gmf.csv", index=False)
(folder / "job.ini").write_text(
    "[general]\ndescription = rocking exposure export\ncalculation_mode = scenario_damage\n"
    "exposure_file = exposure.xml\nstructural_fragility_file = fragility.xml\n"
    f"sites_csv = sites.csv\ngmfs_file = gmf.csv\nnumber_of_ground_motion_fields = {len(pgas)}\n")
logs.dbcmd("upgrade_db")
with logs.init(str(folder / "job.ini"), log_level="error") as log:
    calc = base.calculators(log.get_oqparam(), log.calc_id)
    calc.run()
    ds = calc.datastore
    ids = [i.decode() for i in ds["assetcol/array"]["id"]]
    damages = ds["damages-rlzs"][:, 0]  # asset × damage state (structured), realisation 0
    out = {i: [float(v) for v in damages[k]] for k, i in enumerate(ids)}
    print(json.dumps({"damages": out, "taxonomies": sorted(set(assets["taxonomy"]))}))
