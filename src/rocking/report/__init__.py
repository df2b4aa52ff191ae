"""The study's HTML report and its text: the document (:mod:`.html`), the figures read back with
their sidecars (:mod:`.entries`), the findings (:mod:`.findings`), what was run
(:mod:`.run_summary`), the tables (:mod:`.tables`) and the risk section (:mod:`.risk`). It
only reads what the figures and the study wrote."""
