# Ensemble statistics over the motions of a study: mean, std, median, count per
# (mode, limit_state, tan_alpha, R).


rule mean_spectra:
    input:
        complete=rules.spectra.output.done,
    output:
        nc=out_path("{study}/mean_spectra.nc"),
        csv=report(
            out_path("{study}/mean_spectra.csv"),
            caption="../report/mean_spectra.rst",
            category="Performance spectra",
            labels={"study": "{study}", "table": "ensemble statistics"},
        ),
    params:
        store=lambda wildcards: product_store("spectra", wildcards.study),
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/mean_spectra.log"),
    script:
        "../scripts/mean_spectra.py"
