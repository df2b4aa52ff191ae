"""A study's configuration, typed once where it enters: the schema's fields and their checked
parsing (:mod:`.fields`), the checks run before any work (:mod:`.checks`), and the typed
specs a run is built from (:mod:`.study`, :mod:`.ensemble`, :mod:`.products`, :mod:`.plan`,
:mod:`.damping`, :mod:`.dimensions`)."""
