#!/usr/bin/env python3
"""Locate the handles a mesh's voxel model has and its mesh lacks.

For a segmentation written by `skelseg segment MESH -o OUT` (labels.nrrd,
report.json, segmentation.seg) and its mesh, this finds the places where the
voxel model joins surfaces that are far apart on the mesh and tells which of
them carry a handle of the whole voxel model:

1. every solid voxel whose centre lies within one voxel of the surface gets
   its nearest triangle (dense surface samples);
2. two 26-neighbouring such voxels whose nearest triangles are far apart on
   the mesh (no path along edges within 3 voxels + 2 x their distance in
   space: the contact separation's test) form a pair; pairs form places
   (26-connected groups of their voxels);
3. each place, grown by one voxel inside the model, is removed from the
   whole model: a place whose removal lowers the whole model's genus carries
   a handle. The same is done with the solid voxels the mesh encloses twice
   or more (winding number of the voxel centre, rays along x; grown by two
   voxels, as the self-overlap clearing does) and with those it does not
   enclose (filled by the voxeliser's sign fill or the thin-part fill);
4. every place the mesh encloses but the model lacks (cleared by a
   separation) of 8 voxels or more is filled back: a place whose filling
   lowers the genus is a clearing that left a ring around it.

For each place that carries a handle it prints the face segments its two
sides belong to (segmentation.seg), its centre, how many of its pairs pass the
contact separation's first test (each voxel beyond the other's surface: a
contact the separation found and kept) and how many of its voxels the mesh
encloses twice or more (a self-overlap kept) or not at all (a gap filled by
the voxeliser or the thin-part fill).

Usage: trace_handles.py OUT [OUT ...]   (the mesh is read from report.json)
"""

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse import csgraph
from scipy.spatial import cKDTree

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cut_separation import read_nrrd  # noqa: E402  (one labels.nrrd reader for the bench scripts)


def read_mesh(path):
    vertices, faces = [], []
    if path.lower().endswith(".obj"):
        with open(path) as f:
            for line in f:
                if line.startswith("v "):
                    vertices.append([float(x) for x in line.split()[1:4]])
                elif line.startswith("f "):
                    ids = [int(t.split("/")[0]) for t in line.split()[1:]]
                    ids = [i - 1 if i > 0 else len(vertices) + i for i in ids]
                    for k in range(1, len(ids) - 1):
                        faces.append([ids[0], ids[k], ids[k + 1]])
    elif path.lower().endswith(".off"):
        with open(path) as f:
            tokens = f.read().split()
        assert tokens[0].upper() == "OFF"
        nv, nf = int(tokens[1]), int(tokens[2])
        pos = 4
        for _ in range(nv):
            vertices.append([float(x) for x in tokens[pos:pos + 3]])
            pos += 3
        for _ in range(nf):
            n = int(tokens[pos])
            ids = [int(x) for x in tokens[pos + 1:pos + 1 + n]]
            pos += 1 + n
            for k in range(1, n - 1):
                faces.append([ids[0], ids[k], ids[k + 1]])
    else:
        sys.exit("trace_handles.py: only .obj and .off meshes")
    return np.array(vertices), np.array(faces)


CUBE = np.ones((3, 3, 3), bool)


def topology(mask):
    """(genus, objects, cavities) as kernels/VoxelGenus.h counts them."""
    m = np.pad(mask, 1)
    objects = ndimage.label(m, CUBE)[1]
    background, nb = ndimage.label(~m)
    outside = background[0, 0, 0]
    cavities = nb - 1 if outside else nb
    # Euler characteristic of the union of closed unit cubes: a cell of the
    # lattice is present when any cube around it is solid.
    cubes = int(m.sum())
    # cells: vertices (no axis spanned), edges (one), faces (two)
    counts = {}
    for spanned in [(), (0,), (1,), (2,), (0, 1), (0, 2), (1, 2)]:
        r = m
        for a in range(3):
            if a in spanned:
                continue
            pad = [(0, 0)] * 3
            pad[a] = (1, 1)
            rp = np.pad(r, pad)
            lo = [slice(None)] * 3
            hi = [slice(None)] * 3
            lo[a] = slice(None, -1)
            hi[a] = slice(1, None)
            r = rp[tuple(lo)] | rp[tuple(hi)]
        counts[spanned] = int(r.sum())
    vertices = counts[()]
    edges = counts[(0,)] + counts[(1,)] + counts[(2,)]
    faces = counts[(0, 1)] + counts[(0, 2)] + counts[(1, 2)]
    chi = vertices - edges + faces - cubes
    return objects + cavities - chi, objects, cavities


def winding_numbers(points, V, F):
    """Winding number of each point (rays along +x, signed crossings)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    normal_x = (b[:, 1] - a[:, 1]) * (c[:, 2] - a[:, 2]) - (b[:, 2] - a[:, 2]) * (c[:, 1] - a[:, 1])
    out = np.zeros(len(points), int)
    for i, p in enumerate(points):
        py, pz = p[1] + 1.3e-7, p[2] + 0.7e-7
        # barycentric in the yz projection
        d = (b[:, 1] - a[:, 1]) * (c[:, 2] - a[:, 2]) - (c[:, 1] - a[:, 1]) * (b[:, 2] - a[:, 2])
        ok = np.abs(d) > 1e-18
        u = ((py - a[:, 1]) * (c[:, 2] - a[:, 2]) - (c[:, 1] - a[:, 1]) * (pz - a[:, 2]))
        v = ((b[:, 1] - a[:, 1]) * (pz - a[:, 2]) - (py - a[:, 1]) * (b[:, 2] - a[:, 2]))
        with np.errstate(divide="ignore", invalid="ignore"):
            u = u / d
            v = v / d
        with np.errstate(invalid="ignore"):
            hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1)
            x = a[:, 0] + u * (b[:, 0] - a[:, 0]) + v * (c[:, 0] - a[:, 0])
            hit &= x > p[0]
        out[i] = int(np.sum(np.sign(normal_x[hit])))
    return out


def winding_grid(shape, origin, h, V, F):
    """Winding number of every voxel centre: signed crossings of rays along +x."""
    crossings = {}
    P = (V - origin) / h  # index coordinates (voxel centres at integers)
    for t in F:
        a, b, c = P[t[0]], P[t[1]], P[t[2]]
        d = (b[1] - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (b[2] - a[2])
        if abs(d) < 1e-12:
            continue
        lo = np.ceil(np.minimum(np.minimum(a, b), c)[1:]).astype(int)
        hi = np.floor(np.maximum(np.maximum(a, b), c)[1:]).astype(int)
        lo = np.maximum(lo, 0)
        hi = np.minimum(hi, np.array(shape[1:]) - 1)
        if np.any(hi < lo):
            continue
        jj, kk = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
        py = jj.ravel() + 1.3e-5
        pz = kk.ravel() + 0.7e-5
        u = ((py - a[1]) * (c[2] - a[2]) - (c[1] - a[1]) * (pz - a[2])) / d
        v = ((b[1] - a[1]) * (pz - a[2]) - (py - a[1]) * (b[2] - a[2])) / d
        hit = (u >= 0) & (v >= 0) & (u + v <= 1)
        x = a[0] + u * (b[0] - a[0]) + v * (c[0] - a[0])
        sign = 1 if d > 0 else -1
        for j, k, xx in zip(jj.ravel()[hit], kk.ravel()[hit], x[hit]):
            crossings.setdefault((j, k), []).append((xx, sign))
    w = np.zeros(shape, np.int8)
    xs = np.arange(shape[0])
    for (j, k), items in crossings.items():
        items.sort()
        pos = np.array([i[0] for i in items])
        sgn = np.array([i[1] for i in items])
        # winding at x: sum of signs of crossings beyond x
        total = np.concatenate([np.cumsum(sgn[::-1])[::-1], [0]])
        w[:, j, k] = total[np.searchsorted(pos, xs, side="right")]
    if w.max() < abs(w.min()):
        w = -w
    return w


def trace(out_dir, regions):
    report = json.load(open(f"{out_dir}/report.json"))
    grid = report["grid"]
    h = grid["voxel_size"]
    origin = np.array(grid["origin"])
    labels = read_nrrd(f"{out_dir}/labels.nrrd")[0].transpose(2, 1, 0)  # (z, y, x) -> (x, y, z)
    mask = labels > 0
    V, F = read_mesh(report["input"]["file"])
    face_segment = np.loadtxt(regions or f"{out_dir}/segmentation.seg", dtype=int)
    genus, objects, cavities = topology(mask)
    mesh_genus = report["input"]["mesh_genus"]
    print(f"{out_dir}: voxel genus {genus} (report {report['input']['voxel_genus']}), "
          f"objects {objects}, cavities {cavities}, mesh genus {mesh_genus}, "
          f"thin-part fill {report['input'].get('thin_part_fill')}")

    # dense surface samples with their triangle
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    longest = np.maximum(np.maximum(np.linalg.norm(b - a, axis=1), np.linalg.norm(c - b, axis=1)),
                         np.linalg.norm(a - c, axis=1))
    n = np.maximum(2, np.ceil(longest / (h / 4)).astype(int))
    samples, owners = [], []
    for k in np.unique(n):
        sel = np.where(n == k)[0]
        i, j = np.meshgrid(np.arange(k + 1), np.arange(k + 1), indexing="ij")
        keep = i + j <= k
        u = (i[keep] / k)[None, :, None]
        v = (j[keep] / k)[None, :, None]
        p = a[sel, None] + u * (b[sel, None] - a[sel, None]) + v * (c[sel, None] - a[sel, None])
        samples.append(p.reshape(-1, 3))
        owners.append(np.repeat(sel, keep.sum()))
    samples = np.concatenate(samples)
    owners = np.concatenate(owners)
    tree = cKDTree(samples)

    solid = np.argwhere(mask)
    centres = origin + (solid) * h
    dist, nearest = tree.query(centres, distance_upper_bound=1.0 * h)
    near = np.isfinite(dist)
    index = -np.ones(mask.shape, np.int64)
    index[tuple(solid[near].T)] = np.arange(near.sum())
    tri = owners[nearest[near]]
    point = samples[nearest[near]]
    cent = centres[near]

    # mesh graph over vertices
    e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    w = np.linalg.norm(V[e[:, 0]] - V[e[:, 1]], axis=1)
    graph = sparse.coo_matrix((w, (e[:, 0], e[:, 1])), shape=(len(V), len(V))).tocsr()
    graph = graph.maximum(graph.T)

    offsets = [(dx, dy, dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
               if (dx, dy, dz) > (0, 0, 0)]
    pa_list, pb_list = [], []
    idx = np.argwhere(index >= 0)
    for o in offsets:
        q = idx + np.array(o)
        inside = np.all((q >= 0) & (q < np.array(mask.shape)), axis=1)
        ia = index[tuple(idx[inside].T)]
        ib = index[tuple(q[inside].T)]
        ok = ib >= 0
        pa_list.append(ia[ok])
        pb_list.append(ib[ok])
    pa_i = np.concatenate(pa_list)
    pb_i = np.concatenate(pb_list)
    ta, tb = tri[pa_i], tri[pb_i]
    diff = ta != tb
    # triangles sharing a vertex are near
    shares = np.zeros(len(ta), bool)
    for s in range(3):
        for t in range(3):
            shares |= F[ta, s] == F[tb, t]
    cand = np.where(diff & ~shares)[0]
    limit = 3 * h + 2 * np.linalg.norm(point[pa_i[cand]] - point[pb_i[cand]], axis=1)
    far = np.zeros(len(cand), bool)
    sources = F[ta[cand], 0]
    order = np.argsort(sources)
    unique_sources, starts = np.unique(sources[order], return_index=True)
    ends = np.append(starts[1:], len(order))
    maxlimit = 3 * h + 2 * 2 * h + 2 * longest.max()
    chunk = 256
    for c0 in range(0, len(unique_sources), chunk):
        srcs = unique_sources[c0:c0 + chunk]
        d = csgraph.dijkstra(graph, indices=srcs, limit=maxlimit)
        for k, s in enumerate(srcs):
            members = order[starts[c0 + k]:ends[c0 + k]]
            targets = F[tb[cand[members]]]
            best = d[k][targets].min(axis=1)
            # the path may end at any vertex of either triangle: allow their size
            slack = longest[ta[cand[members]]] + longest[tb[cand[members]]]
            far[members] = best > limit[members] + slack
    pairs = cand[far]
    flagged = np.zeros(mask.shape, bool)
    for arr in (pa_i[pairs], pb_i[pairs]):
        flagged[tuple(idx[arr].T)] = True
    places, nplaces = ndimage.label(flagged, CUBE)
    # contact test of the separation: each voxel beyond the other's surface
    A, B = cent[pa_i[pairs]], cent[pb_i[pairs]]
    PA, PB = point[pa_i[pairs]], point[pb_i[pairs]]
    beyond = (np.einsum("ij,ij->i", B - PA, A - PA) < 0) & (np.einsum("ij,ij->i", A - PB, B - PB) < 0)
    pair_place = places[tuple(idx[pa_i[pairs]].T)]

    W = winding_grid(mask.shape, origin, h, V, F)
    rows = []

    def evaluate(kind, region, grow, sel):
        grown = region
        for _ in range(grow):
            grown = ndimage.binary_dilation(grown, CUBE)
        grown &= mask
        g2, o2, c2 = topology(mask & ~grown)
        if g2 >= genus:
            return
        seg_pairs = {}
        if sel is not None:
            for s1, s2 in zip(face_segment[ta[pairs[sel]]], face_segment[tb[pairs[sel]]]):
                key = "%d-%d" % tuple(sorted((int(s1), int(s2))))
                seg_pairs[key] = seg_pairs.get(key, 0) + 1
        else:
            vox = np.argwhere(grown)
            _, nn = tree.query(origin + (vox) * h)
            segs, counts = np.unique(face_segment[owners[nn]], return_counts=True)
            seg_pairs = {int(x): int(y) for x, y in zip(segs, counts)}
        centre = origin + (np.argwhere(region).mean(axis=0)) * h
        wn = W[grown]
        rows.append(dict(kind=kind, voxels=int(region.sum()), removed=int(grown.sum()),
                         pairs=int(sel.sum()) if sel is not None else 0,
                         beyond=int(beyond[sel].sum()) if sel is not None else 0,
                         genus_after=int(g2), objects_after=int(o2), cavities_after=int(c2),
                         wn0=int((wn == 0).sum()), wn2=int((wn >= 2).sum()),
                         regions=seg_pairs, centre=[round(float(x), 3) for x in centre]))

    for p in range(1, nplaces + 1):
        evaluate("contact", places == p, 1, pair_place == p)
    for kind, part, grow in (("doubly enclosed", mask & (W >= 2), 2),
                             ("outside the mesh", mask & (W == 0), 1)):
        lab, count = ndimage.label(part, CUBE)
        for p in range(1, count + 1):
            evaluate(kind, lab == p, grow, None)
        print(f"  {kind}: {int(part.sum())} solid voxels in {count} places")
    # Voxels the mesh encloses that the model lacks: cleared by a separation
    # (or thinner than a voxel). A place whose filling lowers the genus is a
    # clearing that left a ring around it (a sleeve).
    cleared = ~mask & (W >= 1)
    lab, count = ndimage.label(cleared, CUBE)
    for p in range(1, count + 1):
        region = lab == p
        if region.sum() < 8:
            continue
        g2, o2, c2 = topology(mask | region)
        if g2 < genus:
            centre = origin + np.argwhere(region).mean(axis=0) * h
            vox = np.argwhere(region)
            _, nn = tree.query(origin + vox * h)
            segs, counts = np.unique(face_segment[owners[nn]], return_counts=True)
            rows.append(dict(kind="cleared, filled back", voxels=int(region.sum()),
                             genus_after=int(g2), objects_after=int(o2), cavities_after=int(c2),
                             regions={int(x): int(y) for x, y in zip(segs, counts)},
                             centre=[round(float(x), 3) for x in centre]))
    print(f"  inside the mesh but empty: {int(cleared.sum())} voxels in {count} places")
    print(f"  far pairs {len(pairs)} in {nplaces} places; places whose removal lowers the genus: {len(rows)}")
    for r in rows:
        print("  " + json.dumps(r))
    return genus, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("outputs", nargs="+", help="skelseg segment output folders")
    parser.add_argument("--regions", metavar="SEG",
                        help="face labels naming the mesh regions (default: OUT/segmentation.seg); "
                        "for a pose sequence, the segmentation of the frame with the most parts")
    args = parser.parse_args()
    for out in args.outputs:
        trace(out, args.regions)


if __name__ == "__main__":
    main()
