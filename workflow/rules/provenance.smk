# Provenance of every derived file (rocking.provenance): each rule's script records, beside
# every output, what made it (<dir>/.provenance/<name>.json: its sha256, the digests of the
# job's inputs and other outputs, the digest of the rule's parameters) and checks every input
# against its record before it reads it (rocking.execution.logs.job). Here, while Snakemake
# plans the run, each output of each job it plans is held against its record: an output that
# was edited or cut short, has no record (a killed job, a file copied in), was made with other
# settings, or from inputs that are no longer the files in front of it (an input of another
# study, or missing: a rule killed before it finished) is said in one line and remade with its
# job, as a missing output would be; the jobs after it follow. Files no planned job writes are
# left as they are. Included last: it adds one input function to every rule. A read-only or
# full output folder is said in one line before any job starts (onstart).

import os
import sys

from snakemake.io import IOFile, apply_wildcards

from rocking import provenance


def _job_settings(rule, wildcards):
    """The digest of a job's parameters, as its script records it (rocking.execution.logs.job):
    a rule's parameters are constants or functions of the wildcards."""
    values = {}
    for name, value in rule.params.items():
        if callable(value):
            value = value(wildcards)
        elif isinstance(value, str):
            value = apply_wildcards(value, wildcards)
        values[name] = value
    return provenance.settings_digest(values, OUTPUT)


def _params_seen_by_snakemake(out):
    """Whether Snakemake itself reruns the job of ``out`` when its parameters changed: its
    params trigger is on and it holds its record of the job (.snakemake/metadata; a folder
    copied with `cp -a`, or whose .snakemake/ was removed, has none). Then Snakemake says
    which parameters changed; else a changed setting is found here only."""
    try:
        return any(getattr(t, "name", str(t)).lower() == "params"
                   for t in workflow.rerun_triggers) \
            and workflow.persistence.metadata(IOFile(out)) is not None
    except Exception:  # noqa: BLE001 - another Snakemake: the records decide alone
        return False


def _made_from(rule):
    """An input function of ``rule`` that adds nothing: it forces the job whose outputs do
    not match their records (Snakemake's DAG is being built when input functions run: its
    forced files are the ones `--forcerun` names)."""

    def stale_outputs(wildcards):
        dag = workflow.dag
        if dag is None:
            return []
        try:
            settings = _job_settings(rule, wildcards)
        except Exception:  # noqa: BLE001 - Snakemake says it itself when it evaluates them
            settings = None
        stale = []
        for pattern in rule.output:
            out = apply_wildcards(pattern, wildcards)
            if os.path.exists(out):
                why = provenance.problem(out, rule=rule.name, settings=settings, fast=True)
                if why is not None and why.startswith("made with other settings") \
                        and _params_seen_by_snakemake(out):
                    # nothing else wrong (provenance.problem says this last): Snakemake reruns
                    # it itself, saying which parameters changed
                    why = None
                if why is not None:
                    stale.append((why.startswith("made "), len(stale), out, why))
        if stale:  # one line per job, naming a changed file before those made with it
            *_, out, why = min(stale)
            more = f" (and {len(stale) - 1} other outputs of its job)" if len(stale) > 1 else ""
            forced = getattr(dag, "forcefiles", None)
            if forced is None:  # a Snakemake without it: refused, with the way out
                raise WorkflowError(f"{out}: {why}: remake it with `snakemake --forcerun "
                                    f"{rule.name}`")
            print(f"provenance: {out}: {why}{more}: remade by rule {rule.name}",
                  file=sys.stderr, flush=True)
            forced.update(o for *_, o, _ in stale)
        return []

    return stale_outputs


for _each in list(workflow.rules):
    if _each.output:
        _each.set_input(provenance=_made_from(_each))


onstart:
    # a read-only or full output folder in one line, before any job starts
    for folder in sorted({os.path.dirname(str(f)) or "." for j in workflow.dag.needrun_jobs()
                          for f in j.output}):
        try:
            provenance.require_writable(folder)
        except ValueError as exc:
            print(f"error: {exc}", file=sys.stderr, flush=True)
            raise SystemExit(1) from None
