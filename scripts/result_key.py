"""The one rule a result's tracer is named by in tables, figures and summaries: records/result_key.h
(ResultKey::label) in Python. Scripts that name tracers import it; none builds or cuts apart the text itself.
Only the standard library, so that the GPU summaries (stdlib only) can import it too."""

# The typed columns of a tracer's row (results/README.md) that the label reads: simt's GPU preset, embree's call
# mode (the full parameters are in the tracer_params column).
TRACER_COLUMNS = ["preset", "mode"]


def result_label(tracer, preset="", mode="", params=None):
    """'simt[preset=h100]', 'embree[mode=packet16]', 'cpu'; with params (every parameter, canonical),
    'simt[preset=h100,l1_tags=4]', the name alone without parameters."""
    detail = params if params is not None else f"preset={preset}" if preset else f"mode={mode}" if mode else ""
    return f"{tracer}[{detail}]" if detail else tracer


def tracer_parameters(row):
    """The tracer's parameters of a CSV row as a dict, from its tracer_params column: canonical `k=v,k=v` in the
    experiment CSVs, the whole label `simt[k=v,...]` in validate's."""
    text = row.get("tracer_params", "") or ""
    if text.endswith("]") and "[" in text:
        text = text.split("[", 1)[1][:-1]
    return dict(kv.split("=", 1) for kv in text.split(",") if "=" in kv)


def row_layout(row):
    """The acceleration structure a row traced (records/result_key.h ResultKey::layout): its bvh column, or for rows
    without one the tracer's bvh parameter; bvh2 when neither names one."""
    return row.get("bvh") or tracer_parameters(row).get("bvh") or "bvh2"


def row_label(row, every_parameter=False):
    """The label of a CSV row's tracer, from its tracer, preset and mode columns (or with every parameter, its
    tracer_params column)."""
    if every_parameter:
        return result_label(row["tracer"], params=row.get("tracer_params", ""))
    return result_label(row["tracer"], row.get("preset", ""), row.get("mode", ""))
