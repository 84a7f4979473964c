# YADE peer check (run by peer_check.py as `yade -n -x yade_check.py`): loads each exported
# <grain>.yade.py, builds its clump three ways and writes what YADE computed as JSON lines:
#   export  add_clump(): members' densities give the disc masses, inertia corrected to discs
#   native  add_clump(exact_inertia=False): YADE's own sum over the spheres (0.4 m r^2)
#   default spheres of the grain's density in one FrictMat, O.bodies.clump as a user would
# Input: PEER_YADE_FILES (paths joined by ':'); output: PEER_YADE_OUT.
import json
import os
from yade import utils, Matrix3
from yade.wrapper import Omega, FrictMat

omega = Omega()


def props(cid):
    st = omega.bodies[cid].state
    rot = st.ori.toRotationMatrix()
    i = st.inertia
    world = rot * Matrix3(i[0], 0, 0, 0, i[1], 0, 0, 0, i[2]) * rot.transpose()
    return {"mass": st.mass, "cx": st.pos[0], "cy": st.pos[1], "izz": world[2, 2]}


rows = []
for path in os.environ["PEER_YADE_FILES"].split(":"):
    ns = {}
    with open(path) as f:
        exec(compile(f.read(), path, "exec"), ns)
    grain = os.path.basename(path)[: -len(".yade.py")]
    rows.append(dict(grain=grain, path="export", **props(ns["add_clump"]())))
    rows.append(dict(grain=grain, path="native", **props(ns["add_clump"](exact_inertia=False))))
    mat = omega.materials.append(FrictMat(density=ns["DENSITY"]))
    ids = [omega.bodies.append(utils.sphere((x, y, 0), r, material=mat)) for x, y, r, m in ns["DISCS"]]
    rows.append(dict(grain=grain, path="default", **props(omega.bodies.clump(ids))))

with open(os.environ["PEER_YADE_OUT"], "w") as f:
    for r in rows:
        f.write(json.dumps(r) + "\n")
print("yade_check: %d rows" % len(rows))
