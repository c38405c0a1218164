"""Options declared once: every node's options are its options struct's, and the Python function
of the same step takes the same options with the same defaults (mereo.options_of lists both)."""
import numpy as np
import pytest

import mereo

F, E, S, K = mereo.features, mereo.extension, mereo.signal, mereo.knowledge

# node kind -> (its library options struct or None, the Python function of the same step or None,
#               the node's own options (not in the struct), options whose node default differs)
NODES = {
    "detect_primitives": ("DetectOptions", F.detect_primitives, set(), set()),
    "detect_edges": ("EdgePrimitiveOptions", F.detect_edge_primitives, set(), set()),
    "estimate_normals": ("NormalOptions", E.estimate_normals, set(), set()),
    "support_plane": ("SupportPlaneOptions", E.find_support_plane, set(), set()),
    "filter_depth": ("DepthFilterOptions", S.filter_depth, set(), set()),
    # the node drops weak hypotheses early; the search function keeps all above 1e-6
    "models": (None, None, {"models", "file"}, set()),
    "match_models": ("MatchOptions", K.recognize, set(), {"min_score"}),
    "interpret": ("InterpretOptions", None, set(), set()),
    "find_regions": ("RegionOptions", None, set(), set()),
    "detect_patches": ("PatchOptions", F.planar_patches, set(), set()),
    "detect_legs": ("LegOptions", F.find_legs, set(), set()),
    "report": (None, None, {"track_probability"}, set()),
    "track_objects": ("TrackOptions", None, set(), set()),
    "odometry": ("OdometryOptions", None, {"replace"}, set()),
}


def as_node_value(info):
    """A struct field's default as the node writes it (lists comma-separated)."""
    d = info["default"]
    return ",".join(d) if info["type"] == "list" else d


def test_every_node_kind_with_options_is_checked():
    with_options = {k for k in mereo.nodes.__all__ if mereo.options_of(k)}
    assert with_options == set(NODES)


@pytest.mark.parametrize("kind", sorted(NODES))
def test_node_options_are_the_struct_fields(kind):
    struct, fn, own, differ = NODES[kind]
    node = {o["name"]: o for o in mereo.options_of(getattr(mereo.nodes, kind))}
    assert node == {o["name"]: o for o in mereo.options_of(kind)}
    fields = {o["name"]: o for o in mereo.options_of(struct)} if struct else {}
    assert set(node) - own == set(fields)
    for name, f in fields.items():
        n = node[name]
        assert n["type"] == ("str" if f["type"] == "list" else f["type"]), name
        assert (n["min"], n["max"], n["choices"], n["doc"]) == (f["min"], f["max"], f["choices"], f["doc"]), name
        if name not in differ:
            assert n["default"] == as_node_value(f), name
    for name in differ:
        assert node[name]["default"] != fields[name]["default"], f"{name}: the defaults agree now: drop the exception"


@pytest.mark.parametrize("kind", sorted(k for k, v in NODES.items() if v[1] is not None))
def test_python_function_takes_the_struct_options(kind):
    struct, fn, _, _ = NODES[kind]
    assert mereo.options_of(fn) == mereo.options_of(struct)
    for o in mereo.options_of(fn):
        assert f"    {o['name']} (" in fn.__doc__, o["name"]  # the docstring lists it with its default


@pytest.fixture(scope="module")
def scene():
    o = mereo.synthetic.SceneOptions()
    o.noise = False
    sf = mereo.synthetic.render(2, o)
    cloud = E.back_project(sf.frame)
    normals = E.estimate_normals(cloud)
    plane = E.find_support_plane(cloud, normals)
    return sf.frame, cloud, normals, plane


def call(kind, scene, **options):
    frame, cloud, normals, plane = scene
    if kind == "detect_primitives":
        segs = F.detect_primitives(cloud, normals, roi=plane.roi, **options)
        return [(s.cls, s.inliers, getattr(s, "radius", 0.0)) for s in segs]
    if kind == "estimate_normals":
        return E.estimate_normals(cloud, **options)
    if kind == "support_plane":
        p = E.find_support_plane(cloud, normals, **options)
        return p.normal, p.d, p.inlier_count
    if kind == "filter_depth":
        return S.filter_depth(frame.depth, **options)
    if kind == "detect_edges":
        return [(s.cls, s.inliers, s.params.get("start_px", s.params.get("center_px")).tolist())
                for s in F.detect_edge_primitives(frame, **options)]
    if kind == "detect_patches":
        return [(s.inliers, s.params["area"]) for s in F.planar_patches(cloud, normals, **options)]
    if kind == "detect_legs":
        patches = F.planar_patches(cloud, normals, up=plane.normal)
        return [(s.inliers, s.params["height"]) for s in F.find_legs(cloud, patches, plane.normal, plane.d, **options)]
    if kind == "match_models":
        segs = F.detect_primitives(cloud, normals, roi=plane.roi)
        lattice = K.recognize(K.load_models(), ["mug", "cup"], segs, **options)
        return [(h.concept, h.assignment, h.score) for h in lattice.hypotheses]
    raise AssertionError(kind)


@pytest.mark.parametrize("kind", sorted(k for k, v in NODES.items() if v[1] is not None))
def test_python_function_accepts_every_option_at_its_default(kind, scene):
    """Every listed option is accepted, and passing the listed defaults changes nothing."""
    struct = NODES[kind][0]
    defaults = {o["name"]: o["default"] for o in mereo.options_of(struct)}
    plain, explicit = call(kind, scene), call(kind, scene, **defaults)
    if isinstance(plain, np.ndarray):
        np.testing.assert_array_equal(plain, explicit)
    elif kind == "support_plane":
        np.testing.assert_array_equal(plain[0], explicit[0])
        assert plain[1:] == explicit[1:]
    else:
        assert plain == explicit


def test_unknown_option_names_the_valid_ones(scene):
    _, cloud, normals, _ = scene
    with pytest.raises(TypeError, match=r"unexpected keyword argument 'epsilom'.*epsilon.*handle_body_min_radius"):
        F.detect_primitives(cloud, normals, epsilom=0.01)
    with pytest.raises(TypeError, match="option 'window' must be int, got"):
        E.estimate_normals(cloud, window="5")
    with pytest.raises(ValueError, match=r"option 'epsilon': 0.5 is outside its range \[0.0001, 0.1\]"):
        F.detect_primitives(cloud, normals, epsilon=0.5)
    with pytest.raises(ValueError, match=r"option 'method': unknown method 'sobel' \(known: fast, covariance\)"):
        E.estimate_normals(cloud, method="sobel")
    with pytest.raises(ValueError, match="option 'classes'"):
        F.detect_primitives(cloud, normals, classes=["plane", "cube"])


def test_node_only_fields_now_reach_python(scene):
    """Fields once settable in graph files only: the handle search's body range and turn."""
    _, cloud, normals, plane = scene
    default = F.detect_primitives(cloud, normals, roi=plane.roi)
    no_handles = F.detect_primitives(cloud, normals, roi=plane.roi, handle_body_max_radius=0.0)
    assert any(s.cls == "torus" for s in default)
    assert not any(s.cls == "torus" for s in no_handles)
    # a list as text, as in graph files
    planes = F.detect_primitives(cloud, normals, classes="plane")
    assert planes and all(s.cls == "plane" for s in planes)


def test_options_of_unknown_names():
    with pytest.raises(ValueError, match="no options struct or node kind.*DetectOptions"):
        mereo.options_of("DetectOption")
    with pytest.raises(ValueError, match="takes no described options"):
        mereo.options_of(F.label_image)


def test_numpy_scalars_are_options(scene):
    frame, cloud, _, _ = scene
    np.testing.assert_array_equal(S.filter_depth(frame.depth, radius=np.int64(2), sigma_space=np.float32(1.5)),
                                  S.filter_depth(frame.depth))
    np.testing.assert_array_equal(E.estimate_normals(cloud, adaptive_window=np.bool_(False), window=5.0),
                                  E.estimate_normals(cloud, adaptive_window=False))
    with pytest.raises(TypeError, match="option 'adaptive_window' must be bool"):
        E.estimate_normals(cloud, adaptive_window=1)
    with pytest.raises(ValueError, match="option 'window': must be int, got '5.5'"):
        E.estimate_normals(cloud, window=5.5)
