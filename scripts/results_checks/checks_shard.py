"""results/shard-overhead.md: the table `scripts/slurm/shard-overhead` printed (its logs, CSVs and CPU times were
in a temporary folder and are not committed). The measured cells are quoted as unrecorded figures; the extra CPU
column, the only one computed from others, is recomputed from the whole run's and the shards' CPU cells."""
from results_checks.core import Figure, Unrecorded, read_file

DOC = "results/shard-overhead.md"
SOURCE = "Made by `scripts/slurm/shard-overhead"


def cells(scene):
    """The cells of the scene's table row in the committed document."""
    line = next(line for line in read_file(DOC).splitlines() if line.startswith(f"| {scene} ("))
    return [c.strip() for c in line.strip().strip("|").split("|")]


def extra(scene):
    """(4 shards' CPU, shards − whole, (shards − whole) / whole) from the row's CPU cells."""
    row = cells(scene)
    whole, shards = float(row[2]), float(row[4])
    return row[4], shards - whole, (shards - whole) / whole


def row_checks(scene, measured):
    """`measured`: the row's cells as printed, up to the 4 shards' CPU (written here: an edit of the table fails)."""
    return [Unrecorded(DOC, f"| {scene} (b71412a5403b) | {measured} |", SOURCE),
            Figure(DOC, "| {} | {:+.2f} s ({:+.0%}) |", lambda: extra(scene), minus="-")]


CHECKS = [
    Unrecorded(DOC, "load average before: 14.21 13.77 12.05", "Binary /work/wt15/build/raycoh; host vm"),
    *row_checks("sibenik", "0.13 + 0.20 | 5.57 | 0.11 + 0.21; 0.16 + 0.26; 0.13 + 0.22; 0.15 + 0.25 | 10.71"),
    *row_checks("country_kitchen", "2.56 + 5.39 | 8.79 | 2.13 + 5.34; 1.99 + 4.96; 2.37 + 5.65; 2.13 + 5.44 | 20.52"),
]
