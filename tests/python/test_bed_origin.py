"""analysis.runs.bed_origin: a run says whether its bed was placed (granudrag place) or poured."""
from analysis.runs.bed_origin import placed


def test_a_run_of_a_placed_bed_says_so_by_its_place_parameters_or_its_columns_pour():
    assert placed({"pour": {"intruder_diameter": 2.0}, "pull": {}}) == 0.0
    assert placed({"pour": {"intruder_diameter": 0.0}, "place": {"depth": 3.0}, "pull": {}}) == 1.0
    # A pull from before the engine copied /parameters/place: the column's pour had no intruder.
    assert placed({"pour": {"intruder_diameter": 0.0}, "pull": {}}) == 1.0
    assert placed({"import-lammps": {}, "pull": {}}) == 0.0      # nothing says it was placed
    assert placed({"pour": {}, "pull": {}}) == 0.0               # the pour's default D (2)
