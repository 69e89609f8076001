"""One contact row's algebra, on its two bodies loaded into plain numbers: the pieces every pass
of the contact solver (solver.py) is written with.

The solver's loops load a row's two bodies into plain numbers (load), work on those, and store
them back once (store). Read and written through the arrays at every step instead, each write
obliges the compiled code to read everything again (it cannot know that the arrays do not
overlap): twice the time. A call handed the Rows tuple itself (16 arrays) would cost about half
a microsecond whatever it does.
"""
from ..core.compiling import kernel


@kernel
def load(lin, ang, i, j):
    """Bodies i's and j's velocity and turning rate from per-body vectors, as one tuple
    (v_ix, v_iy, ω_i, v_jx, v_jy, ω_j); zeros for j < 0, a wall, which does not move."""
    if j >= 0:
        return lin[i, 0], lin[i, 1], ang[i], lin[j, 0], lin[j, 1], ang[j]
    return lin[i, 0], lin[i, 1], ang[i], 0.0, 0.0, 0.0


@kernel
def load_mean(lin, ang, accelerations, dt, i, j):
    """As load, for the mean velocity of the step, lin + ½·a·dt (the solver's w): worked out for
    the rows' bodies alone, rather than as an (n, 2) array for every body at every step."""
    half = 0.5 * dt
    if j >= 0:
        return (lin[i, 0] + half * accelerations[i, 0], lin[i, 1] + half * accelerations[i, 1], ang[i],
                lin[j, 0] + half * accelerations[j, 0], lin[j, 1] + half * accelerations[j, 1], ang[j])
    return lin[i, 0] + half * accelerations[i, 0], lin[i, 1] + half * accelerations[i, 1], ang[i], 0.0, 0.0, 0.0


@kernel
def zero_bodies(rows, count, lin, ang):
    """Per-body vectors (lin (n, 2), ang (n,)) set to 0 for the bodies of rows[:count] only: the
    solver reads and writes no other body's, so it need not clear all n at every step."""
    for r in range(count):
        lin[rows.i[r], 0], lin[rows.i[r], 1], ang[rows.i[r]] = 0.0, 0.0, 0.0
        if rows.j[r] >= 0:
            lin[rows.j[r], 0], lin[rows.j[r], 1], ang[rows.j[r]] = 0.0, 0.0, 0.0


@kernel
def store(lin, ang, i, j, v):
    """Write back what load read."""
    lin[i, 0], lin[i, 1], ang[i] = v[0], v[1], v[2]
    if j >= 0:
        lin[j, 0], lin[j, 1], ang[j] = v[3], v[4], v[5]


@kernel
def inverses(inverse_masses, inverse_inertias, i, j):
    """(1/m_i, 1/I_i, 1/m_j, 1/I_j); a wall's are never used. Multiplying by an inverse is cheaper
    than dividing: a sweep would otherwise wait on a dozen divisions a row."""
    if j >= 0:
        return inverse_masses[i], inverse_inertias[i], inverse_masses[j], inverse_inertias[j]
    return inverse_masses[i], inverse_inertias[i], 0.0, 0.0


@kernel
def relative(v, j, dx, dy, lever_i, lever_j):
    """(v_j - v_i) along (dx, dy) at a contact point of bodies i and j (j < 0: a wall), for the
    pair's loaded vectors v (load). A point at arm a moves at v + ω × a, whose part along d is
    v·d + ω·(a × d): the point's lever about each centre (lever_i, lever_j)."""
    rel = -(v[0] * dx + v[1] * dy + v[2] * lever_i)
    if j >= 0:
        rel += v[3] * dx + v[4] * dy + v[5] * lever_j
    return rel


@kernel
def kicked(v, m, j, nx, ny, l0, l1, l2, l3, normal_impulse, tangent_impulse):
    """The pair's vectors v (load) changed by impulses along a row's normal (nx, ny) and tangent
    (-ny, nx), at its point (levers l0..l3 as Rows.lever): i pushed back, j on. m: inverses."""
    px, py = normal_impulse * nx - tangent_impulse * ny, normal_impulse * ny + tangent_impulse * nx
    vix, viy = v[0] - px * m[0], v[1] - py * m[0]
    wi = v[2] - (normal_impulse * l0 + tangent_impulse * l1) * m[1]
    if j < 0:
        return vix, viy, wi, v[3], v[4], v[5]
    return vix, viy, wi, v[3] + px * m[2], v[4] + py * m[2], v[5] + (normal_impulse * l2 + tangent_impulse * l3) * m[3]


@kernel
def friction_kick(v, m, j, nx, ny, l0, l1, l2, l3, mass_t, limit, accumulated):
    """Coulomb friction at a row on the pair's vectors v: the tangential impulse that stops its
    sliding, with the row's accumulated friction impulse kept within ±limit. Returns (v, the new
    accumulated impulse); the impulse applied is its change."""
    sliding = relative(v, j, -ny, nx, l1, l3)
    total = min(max(accumulated - mass_t * sliding, -limit), limit)
    return kicked(v, m, j, nx, ny, l0, l1, l2, l3, 0.0, total - accumulated), total


@kernel
def meets(v, accelerations, i, j, nx, ny, lever_i, lever_j, gap, dt, rest_speed):
    """A row's closing speed if it meets within the step faster than the rest speed, else 0."""
    closing = relative(v, j, nx, ny, lever_i, lever_j)
    if closing >= -rest_speed:
        return 0.0
    pull = (accelerations[j, 0] * nx + accelerations[j, 1] * ny) if j >= 0 else 0.0
    pull -= accelerations[i, 0] * nx + accelerations[i, 1] * ny
    if gap > -(closing + 0.5 * dt * pull) * dt:
        return 0.0   # still apart at the end of the step
    return closing


@kernel
def coupling(m, j, lever_r_i, lever_s_i, lever_r_j, lever_s_j):
    """The normal velocity change at one point of a manifold per unit normal impulse at another
    (or the same) point, from their normal levers about each centre. m: inverses."""
    k = m[0] + lever_r_i * lever_s_i * m[1]
    if j >= 0:
        k += m[2] + lever_r_j * lever_s_j * m[3]
    return k


@kernel
def couplings(m, j, lr0, lr2, ls0, ls2):
    """k11, k22, k12 of the two points r and s of a manifold (same bodies and normal), from their
    normal levers (lr0, lr2) and (ls0, ls2)."""
    k11 = coupling(m, j, lr0, lr0, lr2, lr2)
    k22 = coupling(m, j, ls0, ls0, ls2, ls2)
    k12 = coupling(m, j, lr0, ls0, lr2, ls2)
    return k11, k22, k12


@kernel
def block(k11, k22, k12, b1, b2):
    """The two points of a face on a face solved together, as Box2D's block solver does: the
    accumulated impulses x >= 0 that bring both closing speeds to their targets, or one of them
    with the other left separating, or none; b1, b2 the closing speeds less the targets with no
    impulse, k the couplings. Solved one point after the other, a resting box would tip a
    little each sweep, and a stack of boxes would lean and walk. Returns (found, x1, x2)."""
    det = k11 * k22 - k12 * k12
    x1, x2, found = 0.0, 0.0, False
    if det > 1e-12 * k11 * k22:
        x1, x2 = (-k22 * b1 + k12 * b2) / det, (k12 * b1 - k11 * b2) / det
        found = x1 >= 0.0 and x2 >= 0.0
    if not found:
        x1, x2 = -b1 / k11, 0.0
        found = x1 >= 0.0 and k12 * x1 + b2 >= 0.0
    if not found:
        x1, x2 = 0.0, -b2 / k22
        found = x2 >= 0.0 and k12 * x2 + b1 >= 0.0
    if not found:
        x1, x2 = 0.0, 0.0
        found = b1 >= 0.0 and b2 >= 0.0
    return found, x1, x2


@kernel
def together(k11, k22, k12, u1, u2, restitution):
    """Both points of a two-point manifold meeting at closing speeds u1, u2: the impulses that give
    each -e times its closing speed at once. Returns (possible, j1, j2): not possible if that
    would need a pull."""
    det = k11 * k22 - k12 * k12
    if det <= 1e-12 * k11 * k22:
        return False, 0.0, 0.0
    b1, b2 = -(1.0 + restitution) * u1, -(1.0 + restitution) * u2
    j1, j2 = (k22 * b1 - k12 * b2) / det, (k11 * b2 - k12 * b1) / det
    return j1 >= 0.0 and j2 >= 0.0, j1, j2
