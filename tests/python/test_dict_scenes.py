"""Scenes from Python dicts (issue 41): a dict with NumPy meshes renders the
bits of the same scene from a JSON file (the mesh inline, and as an OBJ
file), and a committed scene read through load_dict renders as load does."""
import json

import numpy as np
import pytest

import caustica
from conftest import ROOT, sphere_scene


def grid_mesh(n=8):
    """A bumpy n x n grid with per-vertex normals and UVs; every coordinate
    is dyadic, so text of any precision reads back to the same floats."""
    u, v = np.meshgrid(np.arange(n + 1) / n, np.arange(n + 1) / n)
    height = 0.125 * ((np.arange(n + 1)[None, :] + np.arange(n + 1)[:, None]) % 3)
    vertices = np.stack([2 * u - 1, height, 2 * v - 1], axis=-1).reshape(-1, 3).astype(np.float32)
    normals = np.tile(np.array([0.0, 1.0, 0.0], np.float32), (len(vertices), 1))
    normals[::2] = [0.0, 0.75, 0.5]  # unit after normalising; dyadic either way
    uvs = np.stack([u, v], axis=-1).reshape(-1, 2).astype(np.float32)
    quads = [(i * (n + 1) + j, i * (n + 1) + j + 1, (i + 1) * (n + 1) + j + 1, (i + 1) * (n + 1) + j)
             for i in range(n) for j in range(n)]
    indices = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.int32)
    return vertices, indices, normals, uvs


def mesh_scene(mesh_shape):
    d = sphere_scene(width=40, height=30)
    d["scene"]["shapes"] = [d["scene"]["shapes"][0], mesh_shape]
    return d


def test_numpy_mesh_dict_renders_as_the_json_file(tmp_path):
    vertices, indices, normals, uvs = grid_mesh()
    transform = {"translate": [0.0, 0.0, 0.5], "rotate": [0.0, 30.0, 0.0], "scale": 1.5}
    material = {"diffusecolor": [0.2, 0.6, 0.3], "specularcolor": [0.2, 0.2, 0.2], "specularexponent": 20}
    from_dict = caustica.load_dict(mesh_scene({
        "type": "mesh", "vertices": vertices, "indices": indices, "normals": normals, "uvs": uvs,
        "transform": transform, "material": material}))
    assert from_dict.counts["triangles"] == 2 * 8 * 8 + 0  # the sphere is analytic

    as_lists = mesh_scene({"type": "mesh", "vertices": vertices.tolist(), "indices": indices.tolist(),
                           "normals": normals.tolist(), "uvs": uvs.tolist(), "transform": transform,
                           "material": material})
    (tmp_path / "inline.json").write_text(json.dumps(as_lists))
    from_json = caustica.load(tmp_path / "inline.json")

    obj = ["v %r %r %r" % tuple(map(float, p)) for p in vertices]
    obj += ["vt %r %r" % tuple(map(float, t)) for t in uvs]
    obj += ["vn %r %r %r" % tuple(map(float, n)) for n in normals]
    obj += ["f " + " ".join(f"{i + 1}/{i + 1}/{i + 1}" for i in tri) for tri in indices]
    (tmp_path / "grid.obj").write_text("\n".join(obj) + "\n")
    from_obj_file = json.loads(json.dumps(as_lists))
    from_obj_file["scene"]["shapes"][1] = {"type": "mesh", "file": "grid.obj", "transform": transform,
                                           "material": material}
    (tmp_path / "file.json").write_text(json.dumps(from_obj_file))
    from_obj = caustica.load(tmp_path / "file.json")

    images = [caustica.render(s, spp=8, seed=4, quiet=True).image for s in (from_dict, from_json, from_obj)]
    assert images[0].max() > 0
    assert np.array_equal(images[0], images[1]), "the dict and its JSON file differ"
    assert np.array_equal(images[0], images[2]), "the inline mesh and its OBJ file differ"


def test_flat_indices_and_numpy_scalars():
    vertices, indices, _, _ = grid_mesh(4)
    a = caustica.load_dict(mesh_scene({"type": "mesh", "vertices": vertices, "indices": indices}))
    d = mesh_scene({"type": "mesh", "vertices": vertices, "indices": indices.reshape(-1)})
    d["nbounces"] = np.int64(4)
    d["camera"]["fov"] = np.float32(45)
    b = caustica.load_dict(d)
    ia = caustica.render(a, spp=4, quiet=True).image
    ib = caustica.render(b, spp=4, quiet=True).image
    assert np.array_equal(ia, ib)


@pytest.mark.parametrize("name", ["cornell_box.json", "textured_primitives.json"])
def test_a_committed_scene_through_load_dict_renders_as_load(name):
    path = ROOT / "scenes" / name
    d = json.loads(path.read_text())
    from_dict = caustica.load_dict(d, base_dir=path.parent, name=str(path))
    from_file = caustica.load(path)
    a = caustica.render(from_dict, spp=4, width=48, quiet=True, mode="path")
    b = caustica.render(from_file, spp=4, width=48, quiet=True, mode="path")
    assert np.array_equal(a.image, b.image)
