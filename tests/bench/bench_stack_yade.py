# The stack of bench_stack.cpp in YADE (run by it as `yade -n -j1 -x bench_stack_yade.py ARGS`):
# the same cubes, base, materials, damping, gravity and timestep, with YADE's polyhedra and their
# volumetric contact law. The layout is described in bench_stack.cpp, which passes:
#   nx ny nz pitch gap steps dt density kn ks friction_deg damping gravity
# Prints one line: "RESULT cubes contacts touching steps cpu_s wall_s mean_z kinetic_J speed spin":
# touching counts the contacts that press (normal force > 0), cpu_s is user + system seconds of
# this process over the steps alone, speed (m/s) and spin (rad/s) are the largest of a cube; then
# "ENGINES name share ...": each engine's share of the time of the steps.
import math
import resource
import sys
import time

from yade import polyhedra_utils

(nx, ny, nz) = (int(a) for a in sys.argv[1:4])
(pitch, gap) = (float(a) for a in sys.argv[4:6])
steps = int(sys.argv[6])
(dt, density, kn, ks, friction, damping, gravity) = (float(a) for a in sys.argv[7:14])

# YADE's volumetric law: normal force = kn_c * overlap volume, shear force = ks_c * shear
# displacement, with kn_c = young / 2 and ks_c = young * poisson / 2 between two bodies of one
# material. A face contact of area A closed by d overlaps A d, so kn_c = kn gives the normal
# force of a joint of stiffness kn (Pa/m); across a full 1 m^2 face, ks_c = ks (N/m) gives that
# of a joint of shear stiffness ks (Pa/m).
mat = PolyhedraMat(density=density, young=2 * kn, poisson=ks / kn, frictionAngle=math.radians(friction))
O.materials.append(mat)


def box(x0, x1, y0, y1, z0, z1, fixed):
    v = [Vector3(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    return polyhedra_utils.polyhedra(mat, v=v, fixed=fixed)


O.bodies.append(box(-1, nx * pitch + 1, -1, ny * pitch + 1, -1, 0, True))
cubes = []
for i in range(nx):
    for j in range(ny):
        for k in range(nz):
            z0 = gap + k * (1 + gap)
            cubes.append(O.bodies.append(box(i * pitch, i * pitch + 1, j * pitch, j * pitch + 1, z0, z0 + 1, False)))

# verletDist 0: the collider then takes under 1% of the time; a positive one (0.01 m) makes the
# run twice as slow, the interaction loop intersecting the pairs its enlarged boxes keep.
O.engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=0),
    InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()], [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
                    [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()]),
    NewtonIntegrator(damping=damping, gravity=(0, 0, -gravity)),
]
O.dt = dt
O.timingEnabled = True


def cpu():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


c0 = cpu()
w0 = time.time()
O.run(steps, True)
c = cpu() - c0
w = time.time() - w0

mean_z = sum(O.bodies[b].state.pos[2] for b in cubes) / len(cubes)
ke = 0.0
speed = 0.0
spin = 0.0
for b in cubes:
    s = O.bodies[b].state
    wl = s.ori.conjugate() * s.angVel  # spin in the principal frame, where inertia is diagonal
    ke += 0.5 * s.mass * s.vel.squaredNorm() + 0.5 * sum(s.inertia[a] * wl[a] ** 2 for a in range(3))
    speed = max(speed, s.vel.norm())
    spin = max(spin, s.angVel.norm())
contacts = sum(1 for i in O.interactions if i.isReal)
touching = sum(1 for i in O.interactions if i.isReal and i.phys.normalForce.norm() > 0)
print("RESULT %d %d %d %d %.6f %.6f %.9f %.9g %.9g %.9g" % (len(cubes), contacts, touching, steps, c, w, mean_z, ke, speed, spin))
total = sum(e.execTime for e in O.engines)
print("ENGINES " + " ".join("%s %.1f%%" % (e.__class__.__name__, 100.0 * e.execTime / total) for e in O.engines))
sys.stdout.flush()
