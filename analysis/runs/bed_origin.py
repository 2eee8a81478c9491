"""Whether a run's bed was placed (`granudrag place`: an intruder put into a settled column) or
poured with its intruder in place, the paper's protocol: the runs table's column `placed`.

A pull copies its bed's parameters into the run file: /parameters/pour always, and for a placed
bed /parameters/place too. A run pulled from a placed bed by a granudrag from before the copy
records only the column's pour, which says intruder_diameter 0 (a column poured without an
intruder, which only a placement gives one): that is read as placed too. Read from the run file,
not from its path, so a run moved or renamed still says how its bed was made.
"""


def placed(parameters):
    """1.0 for a run whose bed was placed, 0.0 for a poured one (`parameters`: the run file's
    {'pour': {...}, 'place': {...}, ...}, analysis.runs.runs); a float, as the table's other settings."""
    if "place" in parameters:
        return 1.0
    diameter = (parameters.get("pour") or {}).get("intruder_diameter")
    return 1.0 if isinstance(diameter, (int, float)) and not isinstance(diameter, bool) and diameter == 0 else 0.0
