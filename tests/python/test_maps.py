"""cleave.maps: a fracture-mode map finds where half of the crack area is transgranular."""

import csv
import math
import xml.etree.ElementTree as ET

import pytest

import cleave.maps as maps


def write_means(folder, points):
    """A summary_mean.csv as `cleave sweep --seeds` writes it, for (x, y, fraction, peak)."""
    with open(folder / "summary_mean.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["bond.tbn/fracture.sigma_f", "bond.kbn", "runs", "counted",
                    "cracks_transgranular_area_fraction_mean",
                    "cracks_transgranular_area_fraction_sd",
                    "cracks_transgranular_area_fraction_n", "peak_load_N_mean"])
        for x, y, frac, peak in points:
            w.writerow([x, y, 3, 3, frac, 0.01, 3, peak])


def logistic_map():
    # f = x^2 / (x^2 + y^2): transgranular where the boundary is stronger than the grain;
    # half exactly on x = y. The y values sit midway (in log) between the x grid's, where
    # f is symmetric about the crossing, so log-linear interpolation finds x = y exactly.
    xs = [10 ** (u / 2) for u in range(-4, 5)]
    ys = [10 ** -0.75, 10 ** 0.25, 10 ** 1.25]
    return [(x, y, x * x / (x * x + y * y), 1000.0 * min(x, y)) for x in xs for y in ys], ys


def test_the_half_line_of_a_closed_form_map_is_where_it_is_one_half(tmp_path):
    points, ys = logistic_map()
    write_means(tmp_path, points)
    m = maps.fracture_map(tmp_path, x="bond.tbn/fracture.sigma_f", y="bond.kbn",
                          path=tmp_path / "map.svg")
    assert len(m["half"]) == len(ys)
    for x, y in m["half"]:
        assert x == pytest.approx(y, rel=1e-9)
    # The picture is an SVG with both panels drawn.
    root = ET.parse(tmp_path / "map.svg").getroot()
    assert root.tag.endswith("svg")
    assert len([e for e in root.iter() if e.tag.endswith("path")]) > 20


def test_a_level_never_crossed_gives_no_point(tmp_path):
    assert maps.half_line([1, 2, 3], [0, 0, 0], [0.1, 0.2, 0.3]) == []
    # Linear interpolation where the axis is linear: 0.5 between 0.25 at x=1 and 0.75 at x=3.
    assert maps.half_line([1, 3], [5, 5], [0.25, 0.75]) == [(2.0, 5)]


def test_a_missing_fact_names_the_column_and_how_to_add_it(tmp_path):
    points, _ = logistic_map()
    write_means(tmp_path, points)
    with pytest.raises(KeyError, match="--column"):
        maps.fracture_map(tmp_path, x="bond.tbn/fracture.sigma_f", y="bond.kbn",
                          fraction="cracks_at_peak_transgranular_area_fraction")


def test_a_folder_without_a_summary_is_refused(tmp_path):
    with pytest.raises(FileNotFoundError, match="summary"):
        maps.fracture_map(tmp_path, x="a", y="b")

