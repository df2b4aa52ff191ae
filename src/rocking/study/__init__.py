"""A study: the zarr store of a spectrum grid (:mod:`.store`), the Dask cluster that fills it
(:mod:`.cluster`), ensemble statistics (:mod:`.aggregate`), the paper's figures
(:mod:`.figures`) and the HTML report (:mod:`.report`)."""
