"""The Python example of docs/USAGE.md runs as printed and finds the place the simulated robot revisits."""
import contextlib
import io
import math
import re

from conftest import REPO


def test_the_readme_example_matches_the_revisited_map():
    readme = (REPO / "docs" / "USAGE.md").read_text()
    section = readme[readme.index("## Python"):]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    names = {}
    with contextlib.redirect_stdout(io.StringIO()) as out:
        exec(compile(code, "docs/USAGE.md", "exec"), names)  # noqa: S102 - our own documentation
    assert out.getvalue().count("\n") == 3
    partslam, r, query, stored = names["partslam"], names["r"], names["query"], names["stored"]
    truth = partslam.compose(partslam.inverse(stored.T_world_map), query.T_world_map)
    assert r.inlier_fraction > 0.9
    assert max(abs(r.T_map_query[0] - truth[0]), abs(r.T_map_query[1] - truth[1])) <= 0.1
    assert abs(partslam.wrap_angle(r.T_map_query[2] - truth[2])) <= 2 * math.pi / 180
    # The ranking's first map shows the place: the stored map, or a neighbour of it whose anchor lies as close
    # to the query's (maps 97 and 98 lie 0.38 and 0.05 m from the query's anchor and score within 0.01).
    maps, order = names["maps"], names["ranking"].order
    assert maps.index(stored) in order[:2]
    first, at = maps[order[0]].T_world_map, query.T_world_map
    assert math.hypot(first[0] - at[0], first[1] - at[1]) < 0.5
