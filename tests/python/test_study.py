"""rl.study runs a study as `restir study` does and hands its results.csv to pandas."""
import json

from conftest import CORNELL


def test_study_to_pandas(rl, tmp_path):
    study = {
        "description": "a tiny sweep for the Python tests",
        "base": {"integrator": "restir-di", "film.width": 16, "film.height": 16, "render.spp": 1},
        "axes": [{"key": "di.spatial_neighbors", "values": [0, 2]}],
        "scenes": [CORNELL],
        "seeds": 1,
        "frames": 2,
        "metrics": ["time", "relmse"],
        "reference": {"spp": 8},
        "plots": [],
    }
    path = tmp_path / "tiny.json"
    path.write_text(json.dumps(study))
    result = rl.study(str(path), str(tmp_path / "out"))
    df = result.to_pandas()
    assert len(df) == 2
    assert sorted(df["di.spatial_neighbors"]) == [0, 2]
    assert (df["relmse"] > 0).all()
