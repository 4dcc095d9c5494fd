"""Numba kernels of the TSDF map (:mod:`seismo3d.mapping.tsdf`, which holds the public API, the method and its
references): block allocation over a coarse table of block slots, fusion of a depth frame into the touched blocks,
trilinear lookup, raycasting of the zero crossing, the blocks a camera sees, and the dense copy for marching cubes.

Voxels are stored per block: ``tsdf[slot, x, y, z]`` (signed distance / truncation, in [-1, 1]) and
``weight[slot, x, y, z]``; ``grid[bx - origin[0], by - origin[1], bz - origin[2]]`` is a block's slot or -1.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, no_cfunc_wrapper=True)
def allocate_blocks(z, k, rot, trans, vs, b, trunc, grid, origin, coords, stamp, n_blocks, frame):
    """Serial: mark every block within the truncation band along each pixel's ray (every 2nd pixel: a block is
    8 voxels wide, far wider than two pixels' footprint). Returns the touched slots, the block count, and whether the
    pool ran out of slots."""
    h, w = z.shape
    bs = b * vs
    touched = np.empty(len(coords), np.int64)
    n_touched = 0
    full = False
    for v in range(0, h, 2):
        for u in range(0, w, 2):
            d = z[v, u]
            if not d > 0:
                continue
            xc = (u - k[2]) * d / k[0]
            yc = (v - k[3]) * d / k[1]
            norm = np.sqrt(xc * xc + yc * yc + d * d)
            dx, dy, dz = xc / norm, yc / norm, d / norm
            wx = rot[0, 0] * dx + rot[0, 1] * dy + rot[0, 2] * dz
            wy = rot[1, 0] * dx + rot[1, 1] * dy + rot[1, 2] * dz
            wz = rot[2, 0] * dx + rot[2, 1] * dy + rot[2, 2] * dz
            n_steps = int(np.ceil(2.0 * trunc / (0.5 * bs))) + 1
            for s in range(n_steps):
                t = norm - trunc + (2.0 * trunc) * s / max(n_steps - 1, 1)
                px = trans[0] + wx * t
                py = trans[1] + wy * t
                pz = trans[2] + wz * t
                bx = int(np.floor(px / bs)) - origin[0]
                by = int(np.floor(py / bs)) - origin[1]
                bz = int(np.floor(pz / bs)) - origin[2]
                if bx < 0 or by < 0 or bz < 0 or bx >= grid.shape[0] or by >= grid.shape[1] or bz >= grid.shape[2]:
                    continue
                slot = grid[bx, by, bz]
                if slot < 0:
                    if n_blocks >= len(coords):
                        full = True
                        continue
                    slot = n_blocks
                    n_blocks += 1
                    grid[bx, by, bz] = slot
                    coords[slot, 0] = bx + origin[0]
                    coords[slot, 1] = by + origin[1]
                    coords[slot, 2] = bz + origin[2]
                if stamp[slot] != frame:
                    stamp[slot] = frame
                    touched[n_touched] = slot
                    n_touched += 1
    return touched[:n_touched].copy(), n_blocks, full


@numba.njit(cache=True, no_cfunc_wrapper=True, nogil=True, error_model="numpy")
def integrate_blocks(share, n_threads, tsdf, weight, coords, touched, z, k, rot_t, trans, vs, trunc, max_weight):
    """Touched blocks ``share, share + n_threads, ...`` (:func:`seismo3d._threads.run_threads`): project every
    voxel centre into the depth image and update its running average (Curless and Levoy 1996, eq. 5-6; KinectFusion
    eq. 11-12). Each block is written by one share only: the same values for any number of threads."""
    h, w = z.shape
    b = tsdf.shape[1]
    for i in range(share, len(touched), n_threads):
        slot = touched[i]
        for a in range(b):
            gx = (coords[slot, 0] * b + a) * vs
            for c in range(b):
                gy = (coords[slot, 1] * b + c) * vs
                for e in range(b):
                    gz = (coords[slot, 2] * b + e) * vs
                    qx, qy, qz = gx - trans[0], gy - trans[1], gz - trans[2]
                    xc = rot_t[0, 0] * qx + rot_t[0, 1] * qy + rot_t[0, 2] * qz
                    yc = rot_t[1, 0] * qx + rot_t[1, 1] * qy + rot_t[1, 2] * qz
                    zc = rot_t[2, 0] * qx + rot_t[2, 1] * qy + rot_t[2, 2] * qz
                    if zc <= 0:
                        continue
                    u = int(np.floor(k[0] * xc / zc + k[2] + 0.5))
                    v = int(np.floor(k[1] * yc / zc + k[3] + 0.5))
                    if u < 0 or v < 0 or u >= w or v >= h:
                        continue
                    d = z[v, u]
                    if not d > 0:
                        continue
                    sdf = d - zc
                    if sdf < -trunc:
                        continue
                    f = min(1.0, sdf / trunc)
                    w0 = weight[slot, a, c, e]
                    tsdf[slot, a, c, e] = (tsdf[slot, a, c, e] * w0 + f) / (w0 + 1.0)
                    weight[slot, a, c, e] = min(w0 + 1.0, max_weight)


@numba.njit(cache=True, no_cfunc_wrapper=True, inline="always")
def block_slot(grid, origin, bx, by, bz):
    gx, gy, gz = bx - origin[0], by - origin[1], bz - origin[2]
    if gx < 0 or gy < 0 or gz < 0 or gx >= grid.shape[0] or gy >= grid.shape[1] or gz >= grid.shape[2]:
        return -1
    return grid[gx, gy, gz]


@numba.njit(cache=True, no_cfunc_wrapper=True)
def trilinear(tsdf, weight, grid, origin, px, py, pz, vs):
    """TSDF at a world point by trilinear interpolation; NaN when a corner voxel has never been observed."""
    b = tsdf.shape[1]
    shift = int(np.log2(b) + 0.5)
    gx, gy, gz = px / vs, py / vs, pz / vs
    ix, iy, iz = int(np.floor(gx)), int(np.floor(gy)), int(np.floor(gz))
    fx, fy, fz = gx - ix, gy - iy, gz - iz
    lx, ly, lz = ix & (b - 1), iy & (b - 1), iz & (b - 1)
    total = 0.0
    if lx < b - 1 and ly < b - 1 and lz < b - 1:  # the 8 corners share one block: one lookup
        slot = block_slot(grid, origin, ix >> shift, iy >> shift, iz >> shift)
        if slot < 0:
            return np.nan
        for a in range(2):
            wa = fx if a else 1.0 - fx
            for c in range(2):
                wc = fy if c else 1.0 - fy
                for e in range(2):
                    if weight[slot, lx + a, ly + c, lz + e] <= 0:
                        return np.nan
                    total += wa * wc * (fz if e else 1.0 - fz) * tsdf[slot, lx + a, ly + c, lz + e]
        return total
    for a in range(2):
        wa = fx if a else 1.0 - fx
        for c in range(2):
            wc = fy if c else 1.0 - fy
            for e in range(2):
                jx, jy, jz = ix + a, iy + c, iz + e
                slot = block_slot(grid, origin, jx >> shift, jy >> shift, jz >> shift)
                if slot < 0:
                    return np.nan
                lx2, ly2, lz2 = jx & (b - 1), jy & (b - 1), jz & (b - 1)
                if weight[slot, lx2, ly2, lz2] <= 0:
                    return np.nan
                total += wa * wc * (fz if e else 1.0 - fz) * tsdf[slot, lx2, ly2, lz2]
    return total


@numba.njit(cache=True, no_cfunc_wrapper=True, nogil=True)
def raycast(share, n_threads, tsdf, weight, grid, origin, k, rot, trans, vs, trunc, near, far, tile, points, normals):
    """Rows ``share, share + n_threads, ...`` (:func:`seismo3d._threads.run_threads`): march each pixel's ray to the
    first + to - zero crossing of the TSDF (KinectFusion 3.4), within the depth range of its tile's blocks, refine it
    by linear interpolation and take the normal from the TSDF's central-difference gradient. Each pixel is written by
    one share only: the same image for any number of threads. (Threads, not a ``prange`` loop: the ``parallel=True``
    kernel compiled for 6.0-6.8 CPU s on a first run, this one for 3.7-4.2, each call the same CPU s (640 x 480, at
    load 7-8, 2026-11-28).)"""
    h, w = points.shape[0], points.shape[1]
    b = tsdf.shape[1]
    shift = int(np.log2(b) + 0.5)
    bs = b * vs
    for v in range(share, h, n_threads):
        for u in range(w):
            dxc = (u - k[2]) / k[0]
            dyc = (v - k[3]) / k[1]
            norm = np.sqrt(dxc * dxc + dyc * dyc + 1.0)
            dx, dy, dz = dxc / norm, dyc / norm, 1.0 / norm
            wx = rot[0, 0] * dx + rot[0, 1] * dy + rot[0, 2] * dz
            wy = rot[1, 0] * dx + rot[1, 1] * dy + rot[1, 2] * dz
            wz = rot[2, 0] * dx + rot[2, 1] * dy + rot[2, 2] * dz
            z0 = near[v // tile, u // tile]
            z1 = far[v // tile, u // tile]
            if not z1 > z0:
                continue
            t = z0 * norm
            t_end = z1 * norm
            f_prev = np.nan
            t_prev = t
            step = 0.0
            while t < t_end:
                px, py, pz = trans[0] + wx * t, trans[1] + wy * t, trans[2] + wz * t
                ix = int(np.floor(px / vs))
                iy = int(np.floor(py / vs))
                iz = int(np.floor(pz / vs))
                if block_slot(grid, origin, ix >> shift, iy >> shift, iz >> shift) < 0:
                    f_prev = np.nan
                    t_prev = t
                    step = 0.5 * bs
                    t += step
                    continue
                f = trilinear(tsdf, weight, grid, origin, px, py, pz, vs)
                if np.isnan(f):
                    f_prev = np.nan
                    t_prev = t
                    step = vs
                    t += step
                    continue
                if f < 0 and np.isnan(f_prev) and step > vs:
                    # a coarse step jumped over the front half of the band: go back and come in at voxel steps
                    t = t - step + vs
                    step = vs
                    continue
                if f_prev > 0 and f < 0:
                    ts = t_prev + (t - t_prev) * f_prev / (f_prev - f)
                    sx, sy, sz = trans[0] + wx * ts, trans[1] + wy * ts, trans[2] + wz * ts
                    nx = trilinear(tsdf, weight, grid, origin, sx + vs, sy, sz, vs) - \
                        trilinear(tsdf, weight, grid, origin, sx - vs, sy, sz, vs)
                    ny = trilinear(tsdf, weight, grid, origin, sx, sy + vs, sz, vs) - \
                        trilinear(tsdf, weight, grid, origin, sx, sy - vs, sz, vs)
                    nz = trilinear(tsdf, weight, grid, origin, sx, sy, sz + vs, vs) - \
                        trilinear(tsdf, weight, grid, origin, sx, sy, sz - vs, vs)
                    nn = np.sqrt(nx * nx + ny * ny + nz * nz)
                    if nn > 0 and not np.isnan(nn):
                        # world -> camera: R^T (x - t); the gradient points to free space, i.e. towards the camera
                        qx, qy, qz = sx - trans[0], sy - trans[1], sz - trans[2]
                        points[v, u, 0] = rot[0, 0] * qx + rot[1, 0] * qy + rot[2, 0] * qz
                        points[v, u, 1] = rot[0, 1] * qx + rot[1, 1] * qy + rot[2, 1] * qz
                        points[v, u, 2] = rot[0, 2] * qx + rot[1, 2] * qy + rot[2, 2] * qz
                        nx, ny, nz = nx / nn, ny / nn, nz / nn
                        normals[v, u, 0] = rot[0, 0] * nx + rot[1, 0] * ny + rot[2, 0] * nz
                        normals[v, u, 1] = rot[0, 1] * nx + rot[1, 1] * ny + rot[2, 1] * nz
                        normals[v, u, 2] = rot[0, 2] * nx + rot[1, 2] * ny + rot[2, 2] * nz
                    break
                if f_prev < 0 and f > 0:
                    break  # a back face: the ray left a surface from behind
                f_prev = f
                t_prev = t
                step = max(vs, 0.8 * f * trunc) if f > 0 else vs
                t += step


@numba.njit(cache=True, no_cfunc_wrapper=True)
def block_ranges(coords, bs, k, rot_t, trans, min_depth, max_depth, tile, h, w, near, far):
    """Splat every allocated block's bounding box into the tiles of the image it covers: per tile, the nearest and
    farthest depth of its blocks (the raycast's bounds, as InfiniTAM's range image; Kaehler et al. 2015)."""
    th, tw = near.shape
    for i in range(len(coords)):
        zmin, zmax = np.inf, -np.inf
        umin, umax, vmin, vmax = np.inf, -np.inf, np.inf, -np.inf
        behind = False
        for c in range(8):
            px = (coords[i, 0] + (c & 1)) * bs - trans[0]
            py = (coords[i, 1] + ((c >> 1) & 1)) * bs - trans[1]
            pz = (coords[i, 2] + ((c >> 2) & 1)) * bs - trans[2]
            x = rot_t[0, 0] * px + rot_t[0, 1] * py + rot_t[0, 2] * pz
            y = rot_t[1, 0] * px + rot_t[1, 1] * py + rot_t[1, 2] * pz
            z = rot_t[2, 0] * px + rot_t[2, 1] * py + rot_t[2, 2] * pz
            zmin = min(zmin, z)
            zmax = max(zmax, z)
            if z < min_depth:
                behind = True
                continue
            u = k[0] * x / z + k[2]
            v = k[1] * y / z + k[3]
            umin, umax = min(umin, u), max(umax, u)
            vmin, vmax = min(vmin, v), max(vmax, v)
        if zmax < min_depth or zmin > max_depth:
            continue
        if behind:  # the block reaches behind the near plane: it may cover any pixel
            umin, umax, vmin, vmax = 0.0, w - 1.0, 0.0, h - 1.0
        if umax < 0 or vmax < 0 or umin > w - 1 or vmin > h - 1:
            continue
        t0 = max(int(np.floor(umin)) // tile, 0)
        t1 = min(int(np.ceil(umax)) // tile, tw - 1)
        s0 = max(int(np.floor(vmin)) // tile, 0)
        s1 = min(int(np.ceil(vmax)) // tile, th - 1)
        z0 = max(zmin, min_depth)
        z1 = min(zmax, max_depth)
        for a in range(s0, s1 + 1):
            for b in range(t0, t1 + 1):
                if z0 < near[a, b]:
                    near[a, b] = z0
                if z1 > far[a, b]:
                    far[a, b] = z1


@numba.njit(cache=True, no_cfunc_wrapper=True)
def fill_dense(tsdf, weight, coords, box_lo, out):
    """Copy observed voxels of the blocks overlapping ``out`` (voxel box starting at ``box_lo``) into it."""
    b = tsdf.shape[1]
    nx, ny, nz = out.shape
    for slot in range(len(coords)):
        x0 = coords[slot, 0] * b - box_lo[0]
        y0 = coords[slot, 1] * b - box_lo[1]
        z0 = coords[slot, 2] * b - box_lo[2]
        if x0 + b <= 0 or x0 >= nx:
            continue
        for a in range(b):
            x = x0 + a
            if x < 0 or x >= nx:
                continue
            for c in range(b):
                y = y0 + c
                if y < 0 or y >= ny:
                    continue
                for e in range(b):
                    zz = z0 + e
                    if zz < 0 or zz >= nz:
                        continue
                    if weight[slot, a, c, e] > 0:
                        out[x, y, zz] = tsdf[slot, a, c, e]
