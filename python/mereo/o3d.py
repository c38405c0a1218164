"""Open3D interop (pip install mereo[open3d]): frames from Open3D, clouds and primitives to it.

    import open3d as o3d, mereo, mereo.o3d

    frame = mereo.o3d.frame_from_rgbd(rgbd, intrinsic)          # o3d.geometry.RGBDImage + PinholeCameraIntrinsic
    frame = mereo.o3d.frame_from_pointcloud(pcd, 480, 640)      # an organized o3d.t.geometry.PointCloud
    result = mereo.recognize(frame)
    pcd = mereo.o3d.to_pointcloud(cloud, normals, colors)        # (H, W, 3) arrays -> o3d.t.geometry.PointCloud
    o3d.visualization.draw_geometries(mereo.o3d.primitive_meshes(result) + [pcd.to_legacy()])

Clouds keep their organization: an (H, W) cloud becomes H * W points in row order, NaN where the
pixel has no depth, so that it comes back as the same (H, W) arrays (cloud_from_pointcloud).
Open3D is imported on first use: without it, these functions raise ImportError naming the extra.
"""
from __future__ import annotations

import numpy as np

__all__ = ["frame_from_rgbd", "frame_from_pointcloud", "to_pointcloud", "cloud_from_pointcloud", "primitive_meshes"]


def _open3d():
    try:
        import open3d
    except ImportError as e:  # (the extra is optional)
        raise ImportError("mereo.o3d needs Open3D: pip install mereo[open3d]") from e
    return open3d


def frame_from_rgbd(rgbd, intrinsic):
    """A mereo.Frame from an open3d.geometry.RGBDImage (depth in metres, as
    RGBDImage.create_from_color_and_depth gives it; 0 = no depth) and its
    open3d.camera.PinholeCameraIntrinsic. A colour image made intensity (the default of
    create_from_color_and_depth) is grey in all three channels."""
    from . import _mereo

    depth = np.asarray(rgbd.depth, dtype=np.float32).copy()
    if depth.ndim != 2:
        raise _mereo.InputError(f"open3d RGBDImage: depth of shape {depth.shape}, expected (H, W)")
    depth[~(depth > 0)] = np.nan
    color = np.asarray(rgbd.color)
    if color.ndim == 2:  # intensity in [0, 1]
        color = np.repeat(color[..., None], 3, axis=2)
    if color.dtype != np.uint8:
        color = np.clip(np.asarray(color, dtype=np.float64) * 255.0 + 0.5, 0, 255).astype(np.uint8)
    if color.shape[:2] != depth.shape:
        raise _mereo.InputError(f"open3d RGBDImage: colour {color.shape[:2]} and depth {depth.shape} differ in size")
    fx, fy = intrinsic.get_focal_length()
    cx, cy = intrinsic.get_principal_point()
    if (intrinsic.width, intrinsic.height) != (depth.shape[1], depth.shape[0]):
        raise _mereo.InputError(f"open3d intrinsic is {intrinsic.width}x{intrinsic.height}, the image "
                                f"{depth.shape[1]}x{depth.shape[0]}")
    f = _mereo.Frame()
    f.depth = depth
    f.color = np.ascontiguousarray(color[..., :3])
    f.intrinsics = _mereo.Intrinsics(fx, fy, cx, cy)
    return f


def to_pointcloud(cloud, normals=None, colors=None):
    """An organized (H, W, 3) cloud (and its normals, its (H, W, 3) uint8 colours) as an
    open3d.t.geometry.PointCloud of H * W points in row order (NaN where there is no point)."""
    o3d = _open3d()
    pts = np.ascontiguousarray(np.asarray(cloud, dtype=np.float32).reshape(-1, 3))
    pcd = o3d.t.geometry.PointCloud(o3d.core.Tensor(pts))
    if normals is not None:
        pcd.point.normals = o3d.core.Tensor(np.ascontiguousarray(np.asarray(normals, dtype=np.float32).reshape(-1, 3)))
    if colors is not None:
        c = np.asarray(colors).reshape(-1, 3)
        c = c.astype(np.float32) / 255.0 if c.dtype == np.uint8 else c.astype(np.float32)
        pcd.point.colors = o3d.core.Tensor(np.ascontiguousarray(c))
    return pcd


def cloud_from_pointcloud(pcd, height: int, width: int):
    """(cloud, normals or None, colours or None) as (H, W, 3) arrays from an organized
    open3d.t.geometry.PointCloud (or legacy PointCloud) of height * width points."""
    from . import _mereo

    legacy = not hasattr(pcd, "point")
    pts = np.asarray(pcd.points if legacy else pcd.point.positions.numpy(), dtype=np.float32)
    if pts.shape != (height * width, 3):
        raise _mereo.InputError(f"open3d point cloud of {pts.shape[0]} points is not organized as {height}x{width}")

    def field(name):
        if legacy:
            has = {"normals": pcd.has_normals, "colors": pcd.has_colors}[name]()
            return np.asarray(getattr(pcd, name), dtype=np.float32) if has else None
        return pcd.point[name].numpy().astype(np.float32) if name in pcd.point else None

    normals, colors = field("normals"), field("colors")
    shape = (height, width, 3)
    if colors is not None:
        colors = np.clip(colors * 255.0 + 0.5, 0, 255).astype(np.uint8).reshape(shape)
    return pts.reshape(shape), None if normals is None else normals.reshape(shape), colors


def frame_from_pointcloud(pcd, height: int, width: int, intrinsics=None):
    """A mereo.Frame from an organized Open3D point cloud (camera frame, metres, NaN or z <= 0 where
    there is no depth): its depth, its colours (if any) and the intrinsics given or fitted to the
    points (mereo.extension.fit_intrinsics)."""
    from . import _mereo
    from .extension import fit_intrinsics

    cloud, _, colors = cloud_from_pointcloud(pcd, height, width)
    depth = cloud[..., 2].copy()
    depth[~(depth > 0)] = np.nan
    if intrinsics is None:
        intrinsics, _ = fit_intrinsics(np.ascontiguousarray(cloud))
    f = _mereo.Frame()
    f.depth = depth
    if colors is not None:
        f.color = np.ascontiguousarray(colors)
    f.intrinsics = intrinsics
    return f


def _rotation_to(axis) -> np.ndarray:
    """The rotation taking +z to `axis`."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    z = np.array([0.0, 0.0, 1.0])
    v, c = np.cross(z, a), float(z @ a)
    if np.linalg.norm(v) < 1e-9:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + k + k @ k * (1 / (1 + c))


_COLOURS = [(0.9, 0.3, 0.2), (0.2, 0.6, 0.9), (0.3, 0.8, 0.3), (0.9, 0.7, 0.2), (0.7, 0.4, 0.9), (0.2, 0.8, 0.8)]


def primitive_meshes(result: dict, accepted_only: bool = True) -> list:
    """The parts of a result's objects (a dict of mereo.recognize) as open3d.geometry.TriangleMesh
    objects in the camera frame, one colour per object: cylinders, cones, spheres and tori as
    their shapes, within their extent; planes and free-form regions are left out."""
    o3d = _open3d()
    meshes = []
    objects = [o for o in result.get("objects", []) if "parts" in o and (o.get("accepted") or not accepted_only)]
    for n, o in enumerate(objects):
        colour = _COLOURS[n % len(_COLOURS)]
        for part in o["parts"].values():
            cls = part.get("class")
            if cls == "cylinder":
                m = o3d.geometry.TriangleMesh.create_cylinder(part["radius"], max(part["height"], 1e-3), 32)
                m.rotate(_rotation_to(part["axis"]), center=(0, 0, 0))
                m.translate(part["point"])
            elif cls == "cone" and "half_angle_deg" in part:
                # a frustum: the cone's radii at the ends of its height about its point
                h, r, t = max(part["height"], 1e-3), part["radius"], np.tan(np.radians(part["half_angle_deg"]))
                r0, r1 = max(r - t * h / 2, 1e-4), r + t * h / 2
                m = o3d.geometry.TriangleMesh.create_cylinder(1.0, h, 32)
                v = np.asarray(m.vertices)
                v[:, :2] *= np.where(v[:, 2:3] > 0, r1, r0)
                m.vertices = o3d.utility.Vector3dVector(v)
                m.rotate(_rotation_to(part["axis"]), center=(0, 0, 0))
                m.translate(part["point"])
            elif cls == "sphere":
                m = o3d.geometry.TriangleMesh.create_sphere(part["radius"], 20)
                m.translate(part["center"])
            elif cls == "torus":
                m = o3d.geometry.TriangleMesh.create_torus(part["major_radius"], part["minor_radius"], 40, 12)
                m.rotate(_rotation_to(part["normal"]), center=(0, 0, 0))
                m.translate(part["center"])
            else:
                continue
            m.compute_vertex_normals()
            m.paint_uniform_color(colour)
            meshes.append(m)
    return meshes
