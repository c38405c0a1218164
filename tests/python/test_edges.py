"""The edge modality from Python: edge chains of a colour array, lines and arcs of a frame with
their pixel and 3-D fields, a Segment again from a line's or arc's dict, the detect_edges node."""
import numpy as np
import pytest

import mereo


@pytest.fixture(scope="module")
def rendered():
    return mereo.synthetic.render(9105)


def disc_image():
    """A dark disc of radius 60 about (320, 240) on a light background."""
    v, u = np.mgrid[0:480, 0:640]
    img = np.full((480, 640, 3), 210, np.uint8)
    img[(u - 320) ** 2 + (v - 240) ** 2 <= 60 ** 2] = (40, 60, 150)
    return img


def test_edge_chains_of_a_disc_lie_on_its_outline():
    chains = mereo.signal.detect_edges(disc_image())
    assert chains and chains[0].dtype == np.float32 and chains[0].shape[1] == 2
    assert all(len(a) >= len(b) for a, b in zip(chains, chains[1:]))  # longest first
    r = np.hypot(chains[0][:, 0] - 320, chains[0][:, 1] - 240)
    assert abs(np.median(r) - 59.5) < 1.0  # the edge between the last pixel in and the first out
    with pytest.raises(ValueError, match="sigma"):
        mereo.signal.detect_edges(disc_image(), sigma=0.0)


def test_the_disc_is_one_arc_with_its_colours_inside_and_outside():
    segs = mereo.features.detect_edge_primitives(disc_image())
    arcs = [s for s in segs if s.cls == "arc"]
    assert len(arcs) == 1 and not [s for s in segs if s.cls == "line"]
    a = arcs[0].params
    assert np.allclose(a["center_px"], (320, 240), atol=1.0)
    assert np.allclose(a["axes_px"], (59.5, 59.5), atol=1.0)
    assert a["end_deg"] - a["start_deg"] > 300
    assert np.allclose(a["color_inside"], np.array((40, 60, 150)) / 255, atol=0.03)
    assert np.allclose(a["color_outside"], np.array((210, 210, 210)) / 255, atol=0.03)
    assert "radius" not in a  # no depth: not lifted


def test_lines_and_arcs_of_a_rendered_frame_are_lifted_and_round_trip(rendered):
    segs = mereo.features.detect_edge_primitives(rendered.frame)
    assert {s.cls for s in segs} == {"line", "arc"}
    lifted = [s for s in segs if "center" in s.params or "point" in s.params]
    assert len(lifted) > len(segs) / 3
    for s in segs[:20]:
        assert len(s.pixels) == s.inliers > 0
        again = mereo.knowledge.Segment.from_dict({"class": s.cls, **s.params})
        for k, v in s.params.items():
            assert np.allclose(again.params[k], v), k
    with pytest.raises(ValueError, match="two numbers"):
        mereo.knowledge.Segment("line", start_px=(1, 2, 3, 4))


def test_the_detect_edges_node_lifts_with_the_cloud(rendered):
    g = mereo.Graph()
    src = g.add("frame_source", "source")
    cloud = g.add("back_project", "cloud")
    edges = g.add(mereo.nodes.detect_edges(min_arc_span_deg=90), "edges")
    g.connect(src.frame, cloud.frame)
    g.connect(src.frame, edges.frame)
    g.connect(cloud.cloud, edges.cloud)
    (r,) = g.run([rendered.frame], keep=["edges.segments"])
    segs = r["outputs"]["edges.segments"]
    direct = mereo.features.detect_edge_primitives(rendered.frame, min_arc_span_deg=90)
    assert len(segs) == len(direct) > 0  # the node is the function
    for a, b in zip(segs, direct):
        assert a.cls == b.cls and list(a.params) == list(b.params)
        assert all(np.allclose(a.params[k], b.params[k]) for k in a.params)
    assert all(s.params["end_deg"] - s.params["start_deg"] >= 90 for s in segs if s.cls == "arc")
