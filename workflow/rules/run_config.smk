# The run's configuration, with the schema's defaults filled in, as a file of the Snakemake
# report (`snakemake --report report.html`), next to every figure and its caption.


rule run_config:
    output:
        report(RUN_CONFIG, caption="../report/run_config.rst", category="Configuration"),
    params:
        config=lambda wildcards: config,
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/run_config.log"),
    script:
        "../scripts/run_config.py"
