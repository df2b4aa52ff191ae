"""A study's science over its stores: ensemble statistics (:mod:`.aggregate`), per-record
answers (:mod:`.records`), the multiple-stripe runs (:mod:`.stripes`) and a run held against a
gallery (:mod:`.verify`). Its configuration is :mod:`rocking.config`, its stores
:mod:`rocking.store`, their filling :mod:`rocking.execution`; the figures :mod:`rocking.plot`
and the report :mod:`rocking.report` only read what it wrote."""
