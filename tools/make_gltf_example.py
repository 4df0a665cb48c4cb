#!/usr/bin/env python3
"""Writes the repository's own glTF 2.0 files, generated here rather than
copied from anywhere: the example scene scenes/gltf_example.gltf (rendered by
`caustica render scenes/gltf_example.gltf`) and the seed corpus of the glTF
fuzz target, fuzz/corpus/fuzz_gltf/ (small valid .gltf and .glb files that
reach every part of the importer: indices of each type, interleaved views,
strips and fans, TRS and matrix nodes, cameras, the three punctual lights,
every material extension we read, an embedded PNG texture, samplers and
texture transforms, normal maps with and without tangents, vertex colours,
alpha masks and blends, clearcoat, partial transmission with a volume,
specular).
    tools/make_gltf_example.py            # rewrites both
Deterministic: the same files on every run."""
import base64, json, math, os, struct, zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def png_checker(n=8, a=(230, 230, 230), b=(60, 60, 70)):
    rows = b"".join(b"\0" + bytes(c for x in range(n) for c in (a if (x + y) % 2 == 0 else b)) for y in range(n))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def png_checker_rgba(n=4):
    """An n x n RGBA checker whose odd squares are nearly transparent (alpha 20)."""
    rows = b"".join(b"\0" + bytes(c for x in range(n) for c in ((220, 200, 60, 255) if (x + y) % 2 == 0
                                                                   else (40, 40, 40, 20))) for y in range(n))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", n, n, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


class Builder:
    def __init__(self):
        self.bin = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "caustica tools/make_gltf_example.py"},
                    "bufferViews": [], "accessors": [], "meshes": [], "nodes": [], "materials": []}

    def view(self, data, stride=None):
        while len(self.bin) % 4:
            self.bin += b"\0"
        v = {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)}
        if stride:
            v["byteStride"] = stride
        self.bin += data
        self.doc["bufferViews"].append(v)
        return len(self.doc["bufferViews"]) - 1

    def accessor(self, view, ctype, count, type_, offset=0, minmax=None):
        a = {"bufferView": view, "componentType": ctype, "count": count, "type": type_, "byteOffset": offset}
        if minmax:
            a["min"], a["max"] = minmax
        self.doc["accessors"].append(a)
        return len(self.doc["accessors"]) - 1

    def mesh(self, pos, nor=None, uv=None, idx=None, material=None, mode=4, index_type=5123):
        attrs = {}
        lo = [min(p[k] for p in pos) for k in range(3)]
        hi = [max(p[k] for p in pos) for k in range(3)]
        attrs["POSITION"] = self.accessor(self.view(b"".join(struct.pack("<3f", *p) for p in pos)), 5126,
                                          len(pos), "VEC3", minmax=(lo, hi))
        if nor:
            attrs["NORMAL"] = self.accessor(self.view(b"".join(struct.pack("<3f", *n) for n in nor)), 5126,
                                            len(nor), "VEC3")
        if uv:
            attrs["TEXCOORD_0"] = self.accessor(self.view(b"".join(struct.pack("<2f", *t) for t in uv)), 5126,
                                                len(uv), "VEC2")
        prim = {"attributes": attrs, "mode": mode}
        if idx is not None:
            fmt = {5121: "<B", 5123: "<H", 5125: "<I"}[index_type]
            prim["indices"] = self.accessor(self.view(b"".join(struct.pack(fmt, i) for i in idx)), index_type,
                                            len(idx), "SCALAR")
        if material is not None:
            prim["material"] = material
        self.doc["meshes"].append({"primitives": [prim]})
        return len(self.doc["meshes"]) - 1

    def material(self, m):
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def node(self, n):
        self.doc["nodes"].append(n)
        return len(self.doc["nodes"]) - 1

    def gltf(self, roots):
        d = dict(self.doc)
        d["scenes"] = [{"nodes": roots}]
        d["scene"] = 0
        d["buffers"] = [{"byteLength": len(self.bin),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.bin)).decode()}]
        return json.dumps({k: v for k, v in d.items() if v != []}, indent=1).encode()

    def glb(self, roots):
        d = dict(self.doc)
        d["scenes"] = [{"nodes": roots}]
        d["buffers"] = [{"byteLength": len(self.bin)}]
        j = json.dumps({k: v for k, v in d.items() if v != []}).encode()
        j += b" " * (-len(j) % 4)
        b = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        body = struct.pack("<I4s", len(j), b"JSON") + j + struct.pack("<I4s", len(b), b"BIN\0") + b
        return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def cube():
    pos, nor, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u, v = [(axis + 1) % 3, (axis + 2) % 3][::sign]
            base = len(pos)
            for (a, b) in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0, 0, 0]
                p[axis], p[u], p[v] = sign, a, b
                pos.append(p), nor.append(n), uv.append(((a + 1) / 2, (1 - b) / 2))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    return pos, nor, uv, idx


def icosphere(levels=2):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        cache, nf = {}, []
        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
                l = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / l for x in p))
                cache[key] = len(v) - 1
            return cache[key]
        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    return [list(p) for p in v], [list(p) for p in v], [i for tri in f for i in tri]


def quat(axis, degrees):
    s = math.sin(math.radians(degrees) / 2)
    return [axis[0] * s, axis[1] * s, axis[2] * s, math.cos(math.radians(degrees) / 2)]


def example():
    b = Builder()
    b.doc["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_transmission", "KHR_materials_ior",
                               "KHR_materials_emissive_strength"]
    b.doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png_checker()).decode()}]
    b.doc["samplers"] = [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}]
    b.doc["textures"] = [{"source": 0, "sampler": 0}]
    floor_m = b.material({"name": "floor", "pbrMetallicRoughness": {
        "baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 0.8}})
    gold = b.material({"name": "gold", "pbrMetallicRoughness": {
        "baseColorFactor": [1.0, 0.77, 0.34, 1], "metallicFactor": 1.0, "roughnessFactor": 0.35}})
    red = b.material({"name": "red plastic", "pbrMetallicRoughness": {
        "baseColorFactor": [0.75, 0.08, 0.06, 1], "metallicFactor": 0.0, "roughnessFactor": 0.4}})
    glass = b.material({"name": "glass", "pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.0},
                        "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                                       "KHR_materials_ior": {"ior": 1.5}}})
    lamp = b.material({"name": "lamp", "emissiveFactor": [1.0, 0.85, 0.6], "doubleSided": True,
                       "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0},
                       "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6.0}}})
    s = 4.0  # floor half size, tiled 4 x 4 by the texture
    floor = b.mesh([[-s, 0, -s], [-s, 0, s], [s, 0, s], [s, 0, -s]], [[0, 1, 0]] * 4,
                   [[0, 0], [0, 4], [4, 4], [4, 0]], [0, 1, 2, 0, 2, 3], floor_m)
    cp, cn, cu, ci = cube()
    gold_cube = b.mesh(cp, cn, cu, ci, gold)
    red_cube = b.mesh(cp, cn, cu, ci, red)
    sp, sn, si = icosphere(3)
    ball = b.mesh(sp, sn, None, si, glass, index_type=5125)
    panel = b.mesh([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], None, None, [0, 1, 2, 0, 2, 3], lamp)
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1.5, "znear": 0.05}}]
    b.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "directional", "color": [1.0, 0.95, 0.85], "intensity": 2.0},
        {"type": "spot", "color": [0.6, 0.75, 1.0], "intensity": 40.0,
         "spot": {"innerConeAngle": 0.25, "outerConeAngle": 0.5}}]}}
    roots = [
        b.node({"name": "floor", "mesh": floor}),
        # A group: the gold cube and the red one on top, turned together.
        b.node({"name": "stack", "translation": [-1.1, 0, -0.3], "rotation": quat((0, 1, 0), 30),
                "children": [b.node({"name": "gold", "mesh": gold_cube, "translation": [0, 0.6, 0],
                                     "scale": [0.6, 0.6, 0.6]}),
                             b.node({"name": "red", "mesh": red_cube, "translation": [0.1, 1.55, 0],
                                     "rotation": quat((0, 1, 0), 25), "scale": [0.35, 0.35, 0.35]})]}),
        b.node({"name": "glass ball", "mesh": ball, "translation": [0.9, 0.7, 0.4], "scale": [0.7, 0.7, 0.7]}),
        b.node({"name": "lamp", "mesh": panel, "matrix": [0.8, 0, 0, 0, 0, -1, 0, 0, 0, 0, 0.8, 0, 0.3, 3.2, 0.5, 1]}),
        b.node({"name": "camera", "camera": 0, "translation": [0.4, 2.2, 5.2], "rotation": quat((1, 0, 0), -17)}),
        b.node({"name": "sun", "rotation": [-0.40, 0.30, 0.14, 0.85],
                "extensions": {"KHR_lights_punctual": {"light": 0}}}),
        b.node({"name": "spot", "translation": [2.5, 3.0, 2.0], "rotation": quat((1, 0, 0), -60),
                "extensions": {"KHR_lights_punctual": {"light": 1}}}),
    ]
    return b.gltf(roots)


def seeds():
    out = {}
    # Indexed triangle (unsigned byte indices), default material, no camera.
    b = Builder()
    b.mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], idx=[0, 1, 2], index_type=5121)
    b.node({"mesh": 0})
    out["triangle.gltf"] = b.gltf([0])
    out["triangle.glb"] = b.glb([0])
    # Strip and fan, non-indexed; a matrix node with a TRS child; a camera.
    b = Builder()
    b.mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], mode=5)
    b.mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], mode=6)
    b.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
    b.node({"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -3, 1], "children": [1, 2]})
    b.node({"mesh": 0, "translation": [1, 0, 0], "rotation": quat((0, 0, 1), 45), "scale": [2, 1, 1]})
    b.node({"mesh": 1, "camera": 0})
    out["strip_fan_camera.gltf"] = b.gltf([0])
    # Interleaved positions / normals / uvs, unsigned int indices, materials
    # with every extension read, an embedded PNG, the three lights.
    b = Builder()
    data = b"".join(struct.pack("<8f", *p, 0, 0, 1, *t) for p, t in
                    (([0, 0, 0], [0, 0]), ([1, 0, 0], [1, 0]), ([0, 1, 0], [0, 1])))
    v = b.view(data, 32)
    attrs = {"POSITION": b.accessor(v, 5126, 3, "VEC3", 0), "NORMAL": b.accessor(v, 5126, 3, "VEC3", 12),
             "TEXCOORD_0": b.accessor(v, 5126, 3, "VEC2", 24)}
    ind = b.accessor(b.view(struct.pack("<3I", 0, 1, 2)), 5125, 3, "SCALAR")
    b.doc["images"] = [{"bufferView": b.view(png_checker(2)), "mimeType": "image/png"}]
    b.doc["textures"] = [{"source": 0}]
    b.doc["materials"] = [
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 0}},
         "emissiveTexture": {"index": 0}, "emissiveFactor": [1, 1, 1], "doubleSided": True},
        {"extensions": {"KHR_materials_transmission": {"transmissionFactor": 1}, "KHR_materials_ior": {"ior": 1.7},
                        "KHR_materials_emissive_strength": {"emissiveStrength": 3}}},
        {"extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.5, 0.5, 0.5, 1],
                                                                "specularFactor": [0.1, 0.1, 0.1],
                                                                "glossinessFactor": 0.5}}}]
    b.doc["meshes"] = [{"primitives": [dict(attributes=attrs, indices=ind, material=m) for m in range(3)]}]
    b.doc["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "point", "intensity": 5}, {"type": "spot", "spot": {"outerConeAngle": 0.3}},
        {"type": "directional", "color": [1, 0.9, 0.8]}]}}
    b.node({"mesh": 0})
    for i in range(3):
        b.node({"translation": [0, 2, i], "extensions": {"KHR_lights_punctual": {"light": i}}})
    out["materials_lights.gltf"] = b.gltf([0, 1, 2, 3])
    out["materials_lights.glb"] = b.glb([0, 1, 2, 3])
    # Samplers (clamp, mirror, nearest) and KHR_texture_transform on the
    # base colour and emissive textures of one image.
    b = Builder()
    b.doc["extensionsUsed"] = ["KHR_texture_transform"]
    b.doc["images"] = [{"bufferView": b.view(png_checker(4)), "mimeType": "image/png"}]
    b.doc["samplers"] = [{"wrapS": 33071, "wrapT": 33648, "magFilter": 9728}, {"wrapS": 33648, "minFilter": 9987}]
    b.doc["textures"] = [{"source": 0, "sampler": 0}, {"source": 0, "sampler": 1}]
    transform = {"KHR_texture_transform": {"offset": [0.25, -0.5], "rotation": 0.4, "scale": [2, -1], "texCoord": 0}}
    b.doc["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1],
                                                    "baseColorTexture": {"index": 0, "extensions": transform}},
                           "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 1}}]
    b.mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 0, 1]] * 3, [[0, 0], [3, 0], [0, -2]], [0, 1, 2], 0)
    b.node({"mesh": 0})
    out["samplers_transform.gltf"] = b.gltf([0])
    # Normal maps: one primitive with a TANGENT attribute, one without
    # (MikkTSpace's tangents), one without uv (warned); COLOR_0 as
    # normalized unsigned bytes (VEC4) and as floats (VEC3).
    b = Builder()
    b.doc["images"] = [{"bufferView": b.view(png_checker(4, (160, 128, 230), (100, 150, 220))), "mimeType": "image/png"}]
    b.doc["textures"] = [{"source": 0}]
    b.doc["materials"] = [{"normalTexture": {"index": 0, "scale": 0.8},
                           "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.8, 0.7, 1]}}]
    quad = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    m_tangent = b.mesh(quad, [[0, 0, 1]] * 4, [[0, 1], [1, 1], [1, 0], [0, 0]], [0, 1, 2, 0, 2, 3], 0)
    prim = b.doc["meshes"][m_tangent]["primitives"][0]
    prim["attributes"]["TANGENT"] = b.accessor(b.view(struct.pack("<16f", *([1, 0, 0, -1] * 4))), 5126, 4, "VEC4")
    prim["attributes"]["COLOR_0"] = b.accessor(b.view(bytes([255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255,
                                                            255, 255, 255, 128])), 5121, 4, "VEC4")
    b.doc["accessors"][-1]["normalized"] = True
    m_mikk = b.mesh(quad, None, [[0, 0], [2, 0], [2, 2], [0, 2]], [0, 1, 2, 0, 2, 3], 0)
    b.doc["meshes"][m_mikk]["primitives"][0]["attributes"]["COLOR_0"] = b.accessor(
        b.view(struct.pack("<12f", *([0.5, 0.25, 1.0] * 4))), 5126, 4, "VEC3")
    b.mesh(quad, None, None, [0, 2, 1], 0)
    b.node({"mesh": m_tangent})
    b.node({"mesh": m_mikk, "translation": [0, 0, -1], "scale": [-1, 1, 1]})
    b.node({"mesh": 2, "translation": [0, 0, -2]})
    out["normal_map_colours.gltf"] = b.gltf([0, 1, 2])
    # Alpha (MASK over an RGBA texture, BLEND by factor) and the layered and
    # transmissive extensions: clearcoat, partial tinted transmission with a
    # volume, specular.
    b = Builder()
    b.doc["extensionsUsed"] = ["KHR_materials_clearcoat", "KHR_materials_transmission", "KHR_materials_volume",
                               "KHR_materials_specular", "KHR_materials_ior"]
    b.doc["images"] = [{"bufferView": b.view(png_checker_rgba(4)), "mimeType": "image/png"}]
    b.doc["samplers"] = [{"magFilter": 9728}]
    b.doc["textures"] = [{"source": 0, "sampler": 0}]
    b.doc["materials"] = [
        {"alphaMode": "MASK", "alphaCutoff": 0.4,
         "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0, "roughnessFactor": 0.5}},
        {"alphaMode": "BLEND",
         "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.6, 0.9, 0.35], "metallicFactor": 0, "roughnessFactor": 0.5}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.1, 0.1, 1], "metallicFactor": 0, "roughnessFactor": 0.5},
         "extensions": {"KHR_materials_clearcoat": {"clearcoatFactor": 0.9, "clearcoatRoughnessFactor": 0.1,
                                                    "clearcoatTexture": {"index": 0},
                                                    "clearcoatRoughnessTexture": {"index": 0}},
                        "KHR_materials_specular": {"specularFactor": 0.7, "specularColorFactor": [1, 0.8, 0.6]}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.9, 1, 1], "metallicFactor": 0.2, "roughnessFactor": 0.1},
         "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.7},
                        "KHR_materials_ior": {"ior": 1.45},
                        "KHR_materials_volume": {"thicknessFactor": 0.5, "attenuationDistance": 0.8,
                                                 "attenuationColor": [0.9, 0.6, 0.3]}}}]
    for m in range(4):
        b.mesh(quad, [[0, 0, 1]] * 4, [[0, 1], [1, 1], [1, 0], [0, 0]], [0, 1, 2, 0, 2, 3], m)
        b.node({"mesh": m, "translation": [1.2 * m, 0, 0]})
    out["alpha_layers.gltf"] = b.gltf([0, 1, 2, 3])
    return out


if __name__ == "__main__":
    with open(os.path.join(ROOT, "scenes", "gltf_example.gltf"), "wb") as f:
        f.write(example())
    corpus = os.path.join(ROOT, "fuzz", "corpus", "fuzz_gltf")
    os.makedirs(corpus, exist_ok=True)
    for name, data in seeds().items():
        with open(os.path.join(corpus, name), "wb") as f:
            f.write(data)
