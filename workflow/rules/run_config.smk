# The run's configuration, with the schema's defaults filled in, in every study's folder (all
# of a study's outputs are under <root>/<study>/; configurations sharing a root but not their
# study names do not overwrite it), and as a file of the Snakemake report
# (`snakemake --report report.html`), next to every figure and its caption.


rule run_config:
    output:
        report(out_path("{study}/config.yaml"), caption="../report/run_config.rst",
               category="Configuration", labels={"study": "{study}"}),
    params:
        # a hash, not the configuration: short "reason" lines; dask.* left out (it cannot
        # change a number, so changing it reruns nothing). The script writes the config itself
        config_hash=config_hash({k: v for k, v in config.items() if k != "dask"}),
    conda:
        "../envs/rocking.yaml"
    log:
        out_path("logs/{study}/run_config.log"),
    script:
        "../scripts/run_config.py"
