"""Filling a study's stores: the store a compute rule fills (:mod:`.prepare`), every product a
study can make (:mod:`.products`), the task a worker runs on one region (:mod:`.tasks`), the
Dask cluster (:mod:`.cluster`), compilation paid once (:mod:`.warmup`) and a job's log
(:mod:`.logs`)."""
