"""Student submissions for the grader's tests: one per scoring pattern and one per hostile behaviour.

Each is the source text of one file. Most start from the two-link arm's closed
forms (Craig (6.60)-(6.62), the Christoffel C) and change one thing; the test
writes them into separate folders, one per student, as a class would hand them in.
"""
from __future__ import annotations

CLOSED_FORMS = '''
import numpy as np

m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81


def M(q):
    c2 = np.cos(q[1])
    a = l2**2 * m2 + l1 * l2 * m2 * c2
    return np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), a], [a, l2**2 * m2]])


def V(q, qd):
    h = m2 * l1 * l2 * np.sin(q[1])
    return np.array([-h * qd[1] ** 2 - 2 * h * qd[0] * qd[1], h * qd[0] ** 2])


def G(q):
    c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])
    return np.array([m2 * l2 * g * c12 + (m1 + m2) * l1 * g * c1, m2 * l2 * g * c12])


def C(q, qd):
    h = m2 * l1 * l2 * np.sin(q[1])
    return np.array([[-h * qd[1], -h * (qd[0] + qd[1])], [h * qd[0], 0.0]])


def tau(q, qd, qdd):
    return M(q) @ qdd + V(q, qd) + G(q)
'''

NEWTON_EULER = '''
import numpy as np

m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81


def rot_z(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def tau(q, qd, qdd):
    """Craig's outward and inward iterations, written out for the two-link arm."""
    z = np.array([0.0, 0.0, 1.0])
    R = [rot_z(q[0]), rot_z(q[1])]
    P = [np.zeros(3), np.array([l1, 0.0, 0.0])]
    Pc = [np.array([l1, 0.0, 0.0]), np.array([l2, 0.0, 0.0])]
    m = [m1, m2]
    w, wd, vd = np.zeros(3), np.zeros(3), np.array([0.0, g, 0.0])
    F = []
    for i in range(2):
        Rt = R[i].T
        vd = Rt @ (np.cross(wd, P[i]) + np.cross(w, np.cross(w, P[i])) + vd)
        wd = Rt @ wd + np.cross(Rt @ w, qd[i] * z) + qdd[i] * z
        w = Rt @ w + qd[i] * z
        F.append(m[i] * (np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) + vd))
    f, n, out = np.zeros(3), np.zeros(3), np.zeros(2)
    for i in (1, 0):
        R_next = R[i + 1] if i == 0 else np.eye(3)
        P_next = P[i + 1] if i == 0 else np.zeros(3)
        n = R_next @ n + np.cross(Pc[i], F[i]) + np.cross(P_next, R_next @ f)
        f = R_next @ f + F[i]
        out[i] = n @ z
    return out
'''


# The two-link arm's recursion written from the notes' worked example, with one of its misprints copied (and
# gravity left out, or G returning round-off): the student's slip, then the text replaced and what replaces it.
WORKED_EXAMPLE_SLIPS = {
    # ¹F₁ = m₁ ¹v̇₁ on link 1 only
    "example-F1-m1-v1": [("F.append(m[i] * (np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) + vd))",
                          "F.append(m[i] * (vd if i == 0 else np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) "
                          "+ vd))")],
    # ²v̇₂ = ²R² ¹v̇_C₁ with ²R² read as the identity
    "example-v2-identity": [("        vd = Rt @ (np.cross(wd, P[i]) + np.cross(w, np.cross(w, P[i])) + vd)\n",
                             "        vd = Rt @ (np.cross(wd, P[i]) + np.cross(w, np.cross(w, P[i])) + vd) if i == 0 "
                             "else F[0] / m[0]\n")],
    # ¹v̇_C₁ = (−l₁θ̇₁² + g s₁, l₁θ̈₁ + g s₁, 0) as printed, g s₁ in its y component too
    "example-gs1-twice": [("F.append(m[i] * (np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) + vd))",
                           "vc = np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) + vd\n"
                           "        if i == 0:\n"
                           "            vc = np.array([-l1 * qd[0] ** 2 + g * np.sin(q[0]), l1 * qdd[0] + g * np.sin(q[0]), 0.0])\n"
                           "        F.append(m[i] * vc)")],
    "no-gravity": [("m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 9.81", "m1, m2, l1, l2, g = 2.0, 1.0, 0.5, 0.4, 0.0")],
    "G-round-off": [("    return out\n", "    return out\n\n\ndef G(q):\n    return np.full(2, 1e-13)\n")],
}


def worked_example(slip: str) -> str:
    """NEWTON_EULER with one of WORKED_EXAMPLE_SLIPS made."""
    text = NEWTON_EULER
    for old, new in WORKED_EXAMPLE_SLIPS[slip]:
        assert old in text, old
        text = text.replace(old, new)
    return text


def closed_forms(change: str = "", remove: tuple[str, ...] = ()) -> str:
    """The closed forms with some functions removed and ``change`` appended (later definitions win)."""
    text = CLOSED_FORMS
    for name in remove:
        start = text.index(f"\ndef {name}(")
        end = text.find("\ndef ", start + 1)
        text = text[:start] + (text[end:] if end >= 0 else "\n")
    return text + change


SCORING = {
    # expected: status; the terms that lose points (0: all of them, None: some); words the feedback must contain
    "newton_euler": (NEWTON_EULER, "ok", {}, []),
    "closed_forms": (closed_forms(), "ok", {}, []),
    "gravity_sign": (closed_forms("\ng = -9.81\n"), "ok", {"tau": 0, "G": 0},
                     ["[gravity-sign] matches the right answer computed with this slip: gravity with the wrong sign",
                      "the same answer comes from [gravity-sign] gravity with the wrong sign or from [cross-reversed]"]),
    "rounded_g": (closed_forms("\ng = 9.8\n"), "ok", {"tau": 0, "G": 0},
                  ["is the right answer times one constant, about 0.1 % smaller everywhere: a constant rounded"]),
    "swapped_joints": (NEWTON_EULER + "\n_right = tau\n\ndef tau(q, qd, qdd):\n    return _right(q, qd, qdd)[::-1]\n", "ok", {"tau": 0, "M": 0, "V": 0, "G": 0, "C": 0},
                       ["wrong order"]),
    "degrees": (NEWTON_EULER + "\n_right = tau\n\ndef tau(q, qd, qdd):\n    return _right(np.deg2rad(q), qd, qdd)\n", "ok", {"tau": 0, "M": 0, "V": 0, "G": 0, "C": 0},
                ["[degrees] matches the right answer computed with this slip: the angles in degrees (positions read as degrees)"]),
    "wrong_length": (closed_forms("\ndef G(q):\n    return np.zeros(3)\n"), "ok", {"G": 0, "tau": 0},
                     ["returned 3 values, the robot has 2 joints (theta1, theta2)"]),
    "nan_values": (closed_forms("\ndef G(q):\n    return np.array([np.nan, 0.0])\n"), "ok", {"G": 0, "tau": 0},
                   ["NaN or inf"]),
    "doubled_mass_matrix": (closed_forms("\n_right = M\n\ndef M(q):\n    return 2 * _right(q)\n"), "ok", {"M": 0, "tau": 0},
                            ["constant factor of about 2.0"]),
    "wrong_mass_entry": (closed_forms("\n_right = M\n\ndef M(q):\n    out = _right(q)\n    out[0, 1] = out[1, 0] = l2**2 * m2\n"
                                      "    return out\n", remove=("tau",)) + "\n\ndef tau(q, qd, qdd):\n    return M(q) @ qdd + V(q, qd) + G(q)\n",
                         "ok", {"M": 0, "tau": 0}, ["entries M[1,2], M[2,1] are wrong", "the inertia part"]),
    "wrong_coriolis": (closed_forms("\ndef V(q, qd):\n    h = m2 * l1 * l2 * np.sin(q[1])\n"
                                    "    return np.array([-h * qd[1] ** 2 - h * qd[0] * qd[1], h * qd[0] ** 2])\n"),
                       "ok", {"V": 0, "tau": 0}, ["Coriolis coefficient of θ̇1θ̇2 in τ1"]),
    "not_quadratic": (closed_forms("\ndef V(q, qd):\n    h = m2 * l1 * l2 * np.sin(q[1])\n"
                                   "    return np.array([-h * abs(qd[1]) - 2 * h * qd[0] * qd[1], h * qd[0] ** 2])\n"),
                      "ok", {"V": 0, "tau": 0}, ["not quadratic in Θ̇"]),
    "raises": (closed_forms("\ndef M(q):\n    return 1 / 0\n"), "ok", {"M": 0, "tau": 0},
               ["ZeroDivisionError", "(line "]),
    "not_christoffel": (closed_forms("\ndef C(q, qd):\n    h = m2 * l1 * l2 * np.sin(q[1])\n"
                                     "    return np.array([[0.0, -h * (2 * qd[0] + qd[1])], [h * qd[0], 0.0]])\n"),
                        "ok", {"C": 0}, ["satisfies C Θ̇ = V"]),
    "half_right": (closed_forms("\n_right = G\n\ndef G(q):\n    return _right(q) * (1.0 if q[0] < 0 else 1.1)\n"),
                   "ok", {"G": None, "tau": None}, ["agrees on"]),
    "only_gravity": (closed_forms(remove=("tau", "M", "V", "C")), "ok", {"tau": 0, "M": 0, "V": 0, "C": 0},
                     ["not defined: write tau(q, qd, qdd)"]),
}

HOSTILE = {
    # status, words the feedback must contain
    "syntax_error": ("def tau(q, qd, qdd)\n    return q\n", "syntax error", ["line 1"]),
    "forbidden_import": ("import pinocchio\n" + CLOSED_FORMS, "forbidden import", ["pinocchio"]),
    "forbidden_hidden": ("import importlib\n_lib = importlib.import_module('course_' + 'dynamics')\n" + CLOSED_FORMS,
                         "forbidden import", ["course_dynamics"]),
    "no_functions": ("x = 1\n", "no functions", ["defines none of tau"]),
    "exit_at_import": ("raise SystemExit(3)\n", "exited", ["exit(3)"]),
    "hard_exit": ("import os\nos._exit(0)\n", "crashed", ["ended without results"]),
    "busy_loop": ("while True:\n    pass\n", "timeout", ["CPU time"]),
    "sleeper": ("import time\ntime.sleep(10_000)\n", "timeout", ["wall-clock"]),
    "memory_hog": ("import numpy as np\nworkspace = np.zeros((100_000, 100_000))\n", "memory", ["memory"]),
    "chatterbox": ("import sys\nfor _ in range(5000):\n    sys.stdout.write('x' * 1000 + '\\n')\n" + CLOSED_FORMS,
                   "output limit", ["printed"]),
    "tamper": ("open(__file__, 'w').write('overwritten')\n" + CLOSED_FORMS, "file access", ["Read-only file system"]),
    "crash": ("raise RuntimeError('boom')\n", "crashed", ["RuntimeError: boom (line 1)"]),
    # The import guard removed, the name computed: the package is simply not in the submission's Python.
    "guard_removed": ("import sys\nsys.meta_path[:] = [f for f in sys.meta_path if type(f).__name__ != 'ImportGuard']\n"
                      "__import__('pino' + 'cchio')\n" + CLOSED_FORMS, "crashed", ["No module named 'pinocchio'"]),
    # Every site-packages folder on the disk put on the path: there is none to find.
    "path_hunt": ("import os, sys\nsys.meta_path[:] = [f for f in sys.meta_path if type(f).__name__ != 'ImportGuard']\n"
                  "for top in (sys.prefix, '/usr/lib', '/usr/local/lib', '/root', '/home', '/opt'):\n"
                  "    for root, folders, _ in os.walk(top):\n"
                  "        sys.path += [os.path.join(root, f) for f in folders if f.endswith('-packages')]\n"
                  "        folders[:] = [f for f in folders if root.count('/') < 6]\n"
                  "__import__('course_' + 'dynamics')\n" + CLOSED_FORMS, "crashed", ["No module named 'course_dynamics'"]),
}

# Memory outside the address-space limit and the mounts' sizes: refused by the sandbox's seccomp filter.
HIDDEN_MEMORY = '''
import ctypes, os
try:
    os.memfd_create("hoard")
    print("memfd: created")
except OSError as exc:
    print("memfd:", exc.strerror)
libc = ctypes.CDLL(None, use_errno=True)
print("shmget:", "created" if libc.shmget(0, 1 << 20, 0o1600) >= 0 else os.strerror(ctypes.get_errno()))
''' + CLOSED_FORMS

# Odd but honest answers: graded as wrong, never a crash of the grader or a misleading status.
ODD_ANSWERS = closed_forms("\ndef G(q):\n    return [[[[1.0]]]]\n\ndef M(q):\n    return [[1e308, 1e308], [-1e308, 1e308]]\n")

# Submissions that write the results channel themselves: each must be 'invalid result' for itself alone.
FORGE = """import os, sys
with os.fdopen(int(sys.argv[1]), "wb") as channel:
    channel.write({payload})
os._exit(0)
"""
FORGED = {  # Python expressions for the bytes each writes
    "forged_deep": 'b"[" * 200_000 + b"]" * 200_000',
    "forged_big_integer": """b'{"status": "ok", "defined": ["G"], "results": {"G": [{"value": [1' + b"0" * 400 + b', 0.0], """
                          """"shape": [2]}]}}'""",
    "forged_empty_results": """b'{"status": "ok", "defined": ["tau"], "results": []}'""",
    "forged_list_for_text": """b'{"status": "ok", "message": ["x"], "defined": ["tau"], "results": {}}'""",
    "forged_status": """b'{"status": "=HYPERLINK(\\\\"http://example.invalid\\\\")", "defined": [], "results": {}}'""",
    "forged_flood": 'b"[" + b"{}," * (64 * 2**20 // 3) + b"{}]"',
}
HOSTILE |= {name: (FORGE.format(payload=payload), "invalid result", ["cannot be used"]) for name, payload in FORGED.items()}

# Fills every writable mount it can find: each must stop at its size, whatever cgroups the machine has.
FILL_MOUNTS = '''
import os
for folder in ("/dev/shm", "/tmp", "/scratch", "/", "/dev"):
    written = 0
    try:
        for k in range(75):  # 300 MiB in files of 4 MiB (each file under the file-size limit)
            with open(os.path.join(folder, f"fill{k}"), "wb") as handle:
                handle.write(b"x" * 4 * 2**20)
            written += 4
    except OSError as exc:
        pass
    print("filled", folder, written, "MiB")
''' + CLOSED_FORMS

# Behaviours that must not harm the grader or outlive grading; each still defines correct functions.
PROCESSES = '''
import os, subprocess, sys
subprocess.Popen(["sleep", "4242"], start_new_session=True)
if os.fork() == 0:
    os.setsid()
    os.execvp("sleep", ["sleep", "4243"])
children = 0
try:
    for _ in range(500):
        pid = os.fork()
        if pid == 0:
            os.execvp("sleep", ["sleep", "4244"])
        children += 1
except OSError as exc:
    print("fork refused after", children, "children:", exc.strerror)
else:
    print("forked all", children, "children")
''' + CLOSED_FORMS

SNOOP = '''
import os, socket
for folder in ("/", "/submission", "/root", "/home", "/tmp", "/scratch", "/work", "/usr"):
    try:
        print(folder, sorted(os.listdir(folder)))
    except OSError as exc:
        print(folder, "unreadable:", exc.strerror)
try:
    socket.create_connection(("1.1.1.1", 53), timeout=3)
    print("network: connected")
except OSError as exc:
    print("network:", exc.strerror or exc)
print("/etc", sorted(os.listdir("/etc")))
print("/lib/python3/dist-packages exists:", os.path.exists("/lib/python3/dist-packages"))
for secret in ("/etc/shadow", "/etc/shadow-", "/etc/gshadow-", "/proc/self/mountinfo", "/proc/1/cmdline"):
    try:
        print(secret, "has", len(open(secret).read()), "characters")
    except OSError as exc:
        print(secret, "unreadable:", exc.strerror)
''' + CLOSED_FORMS

# What a dynamics answer never needs: each is recorded as an integrity flag (code), and each still scores in full.
FLAGGED = {
    "reads_home": ("try:\n    open('/root/.bashrc').read()\nexcept OSError:\n    pass\n", ["file-read"]),
    "lists_root": ("import os\ntry:\n    os.listdir('/root')\nexcept OSError:\n    pass\n", ["list-folder"]),
    "writes_tmp": ("open('/tmp/pwned', 'w').write('x')\n", ["file-write"]),
    "numpy_writes": ("import numpy as np\ntry:\n    np.savetxt('/submission/x.txt', [1.0])\nexcept OSError:\n    pass\n",
                     ["file-write"]),
    "shell": ("import os\nos.system('true')\n", ["process"]),
    "subprocess": ("import subprocess\ntry:\n    subprocess.run(['true'])\nexcept OSError:\n    pass\n", ["process"]),
    "network": ("import socket\ntry:\n    socket.socket().connect(('10.0.0.1', 80))\nexcept OSError:\n    pass\n",
                ["socket"]),
    "native": ("import ctypes\nctypes.CDLL(None).getpid()\n", ["ctypes"]),
    "frames": ("import sys\nharness = sys._getframe(1).f_globals\n", ["introspection"]),
    "closes_channel": ("import os, sys\nos.close(int(sys.argv[2]))\n", ["channel-closed"]),
    "redirects_channel": ("import os, sys\nos.dup2(os.open('/dev/null', os.O_WRONLY), int(sys.argv[2]))\n",
                          ["channel-closed"]),
    # Ways around the hook that it sees anyway.
    "spoofed_frozen": ("exec(compile(\"try:\\n    open('/root/.bashrc')\\nexcept OSError:\\n    pass\\n\", "
                       "'<frozen importlib._bootstrap>', 'exec'))\n", ["file-read"]),
    "frames_removed": ("import glob, importlib._bootstrap as b\nb._call_with_frames_removed(glob.glob, '/root/*')\n",
                       ["list-folder"]),
    "own_module": ("import sys\nopen('helper.py', 'w').write('import os\\nos.system(\"true\")\\n')\n"
                   "sys.path.insert(0, '.')\nimport helper\n", ["process"]),
    "traceback_frames": ("try:\n    1 / 0\nexcept ZeroDivisionError as exc:\n    harness = exc.__traceback__.tb_frame\n",
                         ["introspection"]),
    "thread_gc": ("import gc\nfrom concurrent.futures import ThreadPoolExecutor\n"
                  "ThreadPoolExecutor().submit(gc.get_objects).result()\n", ["introspection"]),
    "junk_on_channel": ("import os, sys\nos.write(int(sys.argv[2]), b'x')\n", ["channel-closed"]),
    "climbs_out": ("import os\ntry:\n    os.open('../' * 12 + 'etc/hostname', os.O_RDONLY)\nexcept OSError:\n    pass\n",
                   ["file-read"]),
    "lists_a_descriptor": ("import os\nos.listdir(os.open('/usr', os.O_RDONLY))\n", ["file-read", "list-folder"]),
    "borrowed_name": ("import os\n_right = tau if 'tau' in dir() else None\n"
                      "exec(compile(\"def probe():\\n    import os\\n    os.listdir('/root')\\n\", os.__file__, 'exec'))\n"
                      "try:\n    probe()\nexcept OSError:\n    pass\n", ["list-folder", "introspection"]),
    "thread_work": ("import os, threading\nt = threading.Thread(target=os.system, args=('true',))\nt.start()\nt.join()\n",
                    ["process"]),
    "import_side_effect": ("import os\nos.environ['BROWSER'] = 'true'\nimport antigravity\n", ["process"]),
        # Lines forged on the flags' channel: refused (untagged), and the channel says it was written to.
    "forges_a_flag": ("import os, sys\nos.write(int(sys.argv[2]), b'\\nprocess\\tforged by the submission\\n')\n",
                      ["channel-closed"]),
    # An answer whose finalizers are C callables alone, freed inside the harness: only the harness's frames show.
    "c_finalizers": ("import ctypes, functools, os, socket, numpy as np\n"
                     "class Shell(np.ndarray):\n    __del__ = functools.partial(os.system, 'true')\n"
                     "class Native(np.ndarray):\n    __del__ = functools.partial(ctypes.CDLL, None)\n"
                     "class Network(np.ndarray):\n    __del__ = functools.partial(socket.socket)\n"
                     "class Listing(np.ndarray):\n    __del__ = functools.partial(os.listdir, '/')\n"
                     "class Reading(np.ndarray):\n    __del__ = functools.partial(open, '/dev/zero', 'rb')\n"
                     "def quiet(value):\n    for kind in (Shell, Native, Network, Listing, Reading):\n"
                     "        value = value.view(kind)  # each view holds the one before: all freed at once\n"
                     "    return value\n", ["file-read", "list-folder", "process", "socket", "ctypes"]),
# What a dynamics answer may do: its own folder, its working folder, warnings, numpy's and the library's files.
    "honest_files": ("import os, warnings, json, numpy as np\nfrom collections import namedtuple\n"
                     "open('notes.txt', 'w').write('scratch')\nParameters = namedtuple('Parameters', 'm1 m2')\n"
                     "os.listdir('.')\nopen(__file__).read()\nwarnings.warn('a student warning')\n"
                     "np.save('q.npy', np.zeros(2))\nnp.load('q.npy')\nimport inspect\ninspect.currentframe()\n", []),
}

# Ways to switch the hook off before acting, each followed by ACTS: every route must still end in flags. DISARM walks
# up from a frame and switches off whatever hook state it finds there (an 'armed' entry, a hook's closure cells).
DISARM = """
def disarm(frame):
    while frame is not None:
        for value in [*frame.f_locals.values(), *frame.f_globals.values()]:
            cells = getattr(value, "__closure__", None)
            for cell in cells if isinstance(cells, tuple) else ():
                try:
                    contents = cell.cell_contents
                except ValueError:
                    continue
                if isinstance(contents, dict) and "armed" in contents:
                    contents["armed"] = False
        frame = frame.f_back
"""
ACTS = """
import os, socket, ctypes
try:
    os.listdir('/root')
except OSError:
    pass
os.system('true')
socket.socket().close()
ctypes.CDLL(None).getpid()
"""
ACTED = ["list-folder", "process", "socket", "ctypes"]
ATTACKS = {
    # A function relabelled as the standard library's, climbing with sys._getframe.
    "relabelled": ("import os, sys, types\n" + DISARM + "def climb():\n    disarm(sys._getframe())\n"
                   "climb = types.FunctionType(climb.__code__.replace(co_filename=os.__file__), globals())\nclimb()\n",
                   [*ACTED, "introspection"]),
    # An honest frame lookup, then f_back (no audit event): the harness's frames must hold none of the hook.
    "climbs_f_back": ("import inspect\n" + DISARM + "disarm(inspect.currentframe())\n", ACTED),
    "climbs_traceback": (DISARM + "try:\n    1 / 0\nexcept ZeroDivisionError as exc:\n"
                         "    disarm(exc.__traceback__.tb_frame)\n", [*ACTED, "introspection"]),
    "climbs_generator": (DISARM + "def steps():\n    yield 1\nrunning = steps()\nnext(running)\n"
                         "disarm(running.gi_frame.f_back or __import__('inspect').currentframe())\n",
                         [*ACTED, "introspection"]),
    # The closing line's closure replaced by one whose cells say "disarmed".
    "cell_write": ("import inspect\nframe = inspect.currentframe()\nwhile frame is not None:\n"
                   "    for value in list(frame.f_locals.values()):\n"
                   "        for cell in getattr(value, '__closure__', None) or ():\n"
                   "            if isinstance(getattr(cell, 'cell_contents', None), dict):\n"
                   "                cell.cell_contents = {'armed': False, 'busy': True, 'counts': {}}\n"
                   "    frame = frame.f_back\n", ACTED),
    # The standard library's path functions rewritten, so that every path looks like one of Python's files.
    "code_swap": ("import os\nos.path.realpath.__code__ = (lambda path, *, strict=False: os.__file__).__code__\n",
                  [*ACTED, "tampered", "channel-closed"]),
    "patched_library": ("import os, posixpath\nposixpath._joinrealpath = lambda *args: (os.__file__, True)\n", ACTED),
    # The harness's own globals: its os, whose write keeps only the closing line.
    "harness_globals": ("import os, sys, types\nharness = sys.modules['__main__']\nreal = os.write\n"
                        "harness.os = types.SimpleNamespace(**{**vars(os), 'write': lambda fd, data: real(fd, data) "
                        "if data.startswith(b'\\nend') else len(data)})\n", ACTED),
    # Code of its own run inside the hook, where the hook's frame is: the __str__ of a command given as a path object.
    "inside_hook": ("import inspect, subprocess\n" + DISARM + "class Sneaky:\n    def __fspath__(self):\n"
                    "        return 'true'\n    def __str__(self):\n        disarm(inspect.currentframe())\n"
                    "        return 'true'\nsubprocess.run([Sneaky()])\n", ACTED),
    # A trace function sees every frame, the hook's too.
    "tracer": ("import sys\n" + DISARM + "calls = []\ndef tracer(frame, event, arg):\n    disarm(frame)\n"
               "    calls.append(event)\n    if len(calls) > 100:\n        sys.settrace(None)\n"
               "sys.settrace(tracer)\n", [*ACTED, "tampered", "channel-closed"]),
}
# Raw memory through numpy's __array_interface__ (an address of its own making), walked through gc's links to the
# hook's closure: id() gives the addresses.
RAW_MEMORY = """
import gc, types
import numpy as np
FLAGGED_CODES = ("file-read", "list-folder", "process", "socket", "ctypes", "introspection", "tampered")
class Raw:
    def __init__(self, address, n=1):
        self.__array_interface__ = {"shape": (n,), "typestr": "<u8", "data": (address, False), "version": 3}
def peek(address):
    return int(np.asarray(Raw(address))[0])
slot = [None]
def as_object(address):
    view = np.asarray(Raw(peek(id(slot) + 24)))
    none = int(view[0])
    view[0] = address
    found = slot[0]
    view[0] = none
    return found
gc.collect()
anchor = [0]
gc.collect()
gc.disable()
function_type, start = id(types.FunctionType), id(anchor) - 16
head, steps = peek(start), 0
while head != start and steps < 2_000_000:
    steps += 1
    if peek(head + 24) == function_type:
        f = as_object(head + 16)
        if f.__name__ == "hook" and f.__closure__:
            for cell in f.__closure__:
                value = cell.cell_contents
                if type(value) is types.FunctionType and value.__name__ == "write":
                    for inner in value.__closure__:
                        if type(inner.cell_contents) is dict:
                            inner.cell_contents.update(dict.fromkeys(FLAGGED_CODES, 10**9))
            break
    head = peek(head)
gc.enable()
"""
# Reaching the hook without an audit event: a signal handler, a gc callback, raw memory through numpy (the red
# team's reproducers: each looks for the hook's closure, its counters and its nonce, to fill the counters).
BLIND = """
def blind(frame):
    while frame is not None:
        found = frame.f_locals
        if 'nonce' in found or 'write' in found:
            for cell in getattr(found.get('write'), '__closure__', None) or ():
                if type(cell.cell_contents) is dict:
                    cell.cell_contents.update(dict.fromkeys(FLAG_CODES, 10**9))
            hit.append(found.get('nonce'))
            return
        frame = frame.f_back
FLAG_CODES = ("file-read", "file-write", "list-folder", "process", "socket", "ctypes", "introspection", "tampered",
              "import-outside", "channel-closed")
hit = []
"""
ATTACKS |= {
    "signal_handler": ("import signal, time\n" + BLIND + "signal.signal(signal.SIGALRM, lambda n, frame: blind(frame))\n"
                       "signal.setitimer(signal.ITIMER_REAL, 0.0003, 0.0003)\ndeadline = time.time() + 0.3\n"
                       "while not hit and time.time() < deadline:\n    compile('1', 'x', 'eval')\n"
                       "signal.setitimer(signal.ITIMER_REAL, 0)\nsignal.signal(signal.SIGALRM, signal.SIG_DFL)\n",
                       [*ACTED, "tampered", "channel-closed"]),
    "gc_callback": ("import gc, inspect\n" + BLIND + "def callback(phase, info):\n"
                    "    if not hit and phase == 'start':\n        blind(inspect.currentframe())\n"
                    "gc.callbacks.append(callback)\ngc.set_threshold(1)\nfor _ in range(2000):\n"
                    "    compile('1', 'x', 'eval')\n    if hit:\n        break\n"
                    "gc.callbacks.remove(callback)\ngc.set_threshold(700)\n", [*ACTED, "tampered", "channel-closed"]),
    "raw_memory": (RAW_MEMORY, ["list-folder", "process", "socket", "ctypes", "introspection"]),
}
FLAGGED |= {name: (source + ACTS, codes) for name, (source, codes) in ATTACKS.items()}
# Imports from a folder it put on the path itself, outside the interpreter's path as the harness set it.
FLAGGED["import_outside"] = ("import os, sys, tempfile\nfolder = tempfile.mkdtemp()\n"
                             "open(os.path.join(folder, 'borrowed.py'), 'w').write('VALUE = 1\\n')\n"
                             "sys.path.insert(0, folder)\nimport borrowed\nos.remove(borrowed.__file__)\nos.rmdir(folder)\n",
                             ["file-write", "import-outside"])
# What an honest answer may use of Python: none of it is flagged.
FLAGGED["honest_python"] = ('''
import numpy as np
import inspect, warnings, functools, fractions, statistics, traceback, dataclasses
from collections import namedtuple
State = namedtuple("State", "q qd")

@dataclasses.dataclass
class Link:
    mass: float

def scaled(factor):
    def apply(x):
        return factor * x
    return apply

def joints(n):
    yield from range(n)

@functools.lru_cache
def twice(x):
    return scaled(2)(x)

here = inspect.currentframe()
signature = inspect.signature(twice.__wrapped__)
warnings.warn("a student warning")
total = sum(twice(j) for j in joints(3)) + statistics.mean([1, 2]) + float(fractions.Fraction(1, 3))
try:
    1 / 0
except ZeroDivisionError:
    trace = traceback.format_exc()
state = State(*np.zeros((2, 2)))
class Workspace:
    def __del__(self):
        self.closed = True
Workspace()
norm = functools.partial(np.linalg.norm, axis=0)
rotate = functools.partial(np.dot, np.eye(2))
parameters = [p.name for p in inspect.signature(scaled).parameters.values()]
total += float(norm(rotate(np.ones((2, 2))))[0])
''', [])
FLAGGED = {name: (source + CLOSED_FORMS, codes) for name, (source, codes) in FLAGGED.items()}
FLAGGED["c_finalizers"] = (FLAGGED["c_finalizers"][0] + "\n_G = G\n\ndef G(q):\n    return quiet(_G(q))\n",
                           FLAGGED["c_finalizers"][1])

# With the import guard taken out and the grader's own installation put on the path (the fallback without a
# sandbox has it on the disk), the reference imported and its modules then dropped from sys.modules: the hook saw
# the package load.
HIDDEN_IMPORT = """import sys
sys.path[:0] = {folders!r}
sys.meta_path[:] = [f for f in sys.meta_path if type(f).__name__ != "ImportGuard"]
try:
    _cd = __import__("course_" + "dynamics")
    _arm = _cd.load_robot("two_link")
    _gravity = _cd.gravity_torques   # the package loads its names on first use: taken before the modules go
except ImportError:
    _cd = None
""" + CLOSED_FORMS + """
if _cd is not None:
    def G(q):
        return _gravity(_arm, q)
for _name in [m for m in sys.modules if m.split(".")[0] == "course_dynamics"]:
    del sys.modules[_name]
"""

# An honest answer but for one term: G returns far more values than a term of two joints has. G alone loses its
# points; M and V are still graded.
OVERSIZED_G = closed_forms("\ndef G(q):\n    return np.ones(10000)\n", remove=("tau",)) + \
    "\ndef tau(q, qd, qdd):\n    return M(q) @ qdd + V(q, qd) + np.array([m2 * l2 * g * np.cos(q[0] + q[1]) + " \
    "(m1 + m2) * l1 * g * np.cos(q[0]), m2 * l2 * g * np.cos(q[0] + q[1])])\n"

# A student whose file name and error message carry HTML: both must reach the feedback escaped.
INJECTION_NAME = "mallory<img src=x onerror=alert(1)>"
INJECTION = 'raise RuntimeError("<script>alert(document.cookie)</script>")\n'


SPATIAL_NEWTON_EULER = '''
import numpy as np

# The spatial arm's numbers, as `course-dynamics info spatial_arm` lists them (one entry per link).
R0 = {R0}
P = {P}
m = {m}
Pc = {Pc}
Ic = {Ic}
g = np.array({g})
z = np.array([0.0, 0.0, 1.0])


def rot_z(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def tau(q, qd, qdd):
    """Craig's outward (6.45)-(6.50) and inward (6.51)-(6.53) iterations for a serial arm."""
    n_links = len(m)
    R = [np.array(R0[i]) @ rot_z(q[i]) for i in range(n_links)]  # orientation of frame i in frame i-1
    w, wd, vd = np.zeros(3), np.zeros(3), -g
    F, N = [], []
    for i in range(n_links):
        Rt = R[i].T
        vd = Rt @ (np.cross(wd, P[i]) + np.cross(w, np.cross(w, P[i])) + vd)
        wd = Rt @ wd + np.cross(Rt @ w, qd[i] * z) + qdd[i] * z
        w = Rt @ w + qd[i] * z
        vc = np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i])) + vd
        I = np.array(Ic[i])
        F.append(m[i] * vc)
        N.append(I @ wd + np.cross(w, I @ w))
    f, n, out = np.zeros(3), np.zeros(3), np.zeros(n_links)
    for i in reversed(range(n_links)):
        R_next = R[i + 1] if i + 1 < n_links else np.eye(3)
        P_next = np.array(P[i + 1]) if i + 1 < n_links else np.zeros(3)
        n = N[i] + R_next @ n + np.cross(Pc[i], F[i]) + np.cross(P_next, R_next @ f)
        f = R_next @ f + F[i]
        out[i] = n @ z
    return out
'''

# A student's slips in SPATIAL_NEWTON_EULER: the mistake's code, then the text replaced and what replaces it.
SPATIAL_SLIPS = {
    "rotation-transposed": [("Rt = R[i].T", "Rt = R[i]"), ("R_next = R[i + 1] if", "R_next = R[i + 1].T if")],
    "rotation-transposed-outward": [("Rt = R[i].T", "Rt = R[i]")],
    "cross-reversed": [("np.cross(Rt @ w, qd[i] * z)", "np.cross(qd[i] * z, Rt @ w)")],
    "centripetal-missing": [(" + np.cross(w, np.cross(w, P[i]))", ""), (" + np.cross(w, np.cross(w, Pc[i]))", "")],
    "centripetal-missing-6.48": [(" + np.cross(w, np.cross(w, Pc[i]))", "")],
    "gyroscopic-missing": [("N.append(I @ wd + np.cross(w, I @ w))", "N.append(I @ wd)")],
    "inertia-about-origin": [("I = np.array(Ic[i])", "I = np.array(Ic[i]) + m[i] * (np.dot(Pc[i], Pc[i]) * np.eye(3)"
                                                      " - np.outer(Pc[i], Pc[i]))")],
    "moment-arm-missing": [(" + np.cross(P_next, R_next @ f)", "")],
    "gravity-sign": [("vd = np.zeros(3), np.zeros(3), -g", "vd = np.zeros(3), np.zeros(3), g")],
    "degrees": [("rot_z(q[i])", "rot_z(np.deg2rad(q[i]))")],
    "joints-swapped": [("    return out\n", "    return out[::-1]\n")],
    # gravity added link by link, F = m (v̇_C − g), in the wrong frame
    "gravity-frame-unrotated": [("vd = np.zeros(3), np.zeros(3), -g", "vd = np.zeros(3), np.zeros(3), np.zeros(3)"),
                                ("F.append(m[i] * vc)", "F.append(m[i] * (vc - g))")],
    "gravity-frame-rotated": [("vd = np.zeros(3), np.zeros(3), -g", "vd = np.zeros(3), np.zeros(3), np.zeros(3)"),
                              ("    for i in range(n_links):\n        Rt = R[i].T",
                               "    R0i = np.eye(3)\n    for i in range(n_links):\n        R0i = R0i @ R[i]\n"
                               "        Rt = R[i].T"),
                              ("F.append(m[i] * vc)", "F.append(m[i] * (vc - R0i @ g))")],
    "com-wrong-link": [("vc = np.cross(wd, Pc[i]) + np.cross(w, np.cross(w, Pc[i]))",
                        "vc = np.cross(wd, Pc[i - 1]) + np.cross(w, np.cross(w, Pc[i - 1]))"),
                       ("np.cross(Pc[i], F[i])", "np.cross(Pc[i - 1], F[i])")],
    "tau-from-N": [("out[i] = n @ z", "out[i] = N[i] @ z")],
    "tau-from-child": [("        n = N[i] + R_next", "        n_child = n\n        n = N[i] + R_next"),
                       ("out[i] = n @ z", "out[i] = n_child @ z")],
    # the lecture notes' misprints (reference/errata.md) copied into the code
    "notes-6.48": [("        vd = Rt @ (np.cross(wd, P[i])", "        wd_i = wd\n        vd = Rt @ (np.cross(wd, P[i])"),
                   ("vc = np.cross(wd, Pc[i])", "vc = np.cross(wd_i, Pc[i])")],
    "notes-worked-F1": [("F.append(m[i] * vc)", "F.append(m[i] * vd)")],
    "notes-6.50": [("N.append(I @ wd + np.cross(w, I @ w))",
                    "I_o = I + m[i] * (np.dot(Pc[i], Pc[i]) * np.eye(3) - np.outer(Pc[i], Pc[i]))\n"
                    "        N.append(I @ wd + np.cross(w, I_o @ w))")],
    "notes-6.51": [("f = R_next @ f + F[i]",  # ⁱIᵢ₊₁ as printed: link i+1's tensor (none is needed at the tip)
                    "f = (np.array(Ic[i + 1]) if i + 1 < n_links else np.eye(3)) @ R_next @ f + F[i]")],
    "notes-6.52": [("n = N[i] + R_next @ n + np.cross(Pc[i], F[i]) + np.cross(P_next, R_next @ f)",
                    "N_next = N[i + 1] if i + 1 < n_links else np.zeros(3)\n"
                    "        n = N_next + R_next @ n + np.cross(np.zeros(3), F[i]) + np.cross(P_next, f)")],
    # one of (6.52)'s three misprints copied, the other two terms right
    "notes-6.52-N": [("n = N[i] + R_next", "n = (N[i + 1] if i + 1 < n_links else np.zeros(3)) + R_next")],
    "notes-6.52-PxF": [("np.cross(Pc[i], F[i])", "np.cross(np.array(P[i]), F[i])")],
    "notes-6.52-identity": [("np.cross(P_next, R_next @ f)", "np.cross(P_next, f)")],
    "first-moment-missing": [(" + np.cross(Pc[i], F[i])", "")],
}
# Gravity added link by link and rotated into each frame the right way, ⁱg = ⁰ᵢRᵀ ⁰g: right, as Craig's lift is.
GRAVITY_PER_LINK = [SPATIAL_SLIPS["gravity-frame-rotated"][0], SPATIAL_SLIPS["gravity-frame-rotated"][1],
                    ("F.append(m[i] * vc)", "F.append(m[i] * (vc - R0i.T @ g))")]


def spatial_newton_euler(model, slip: str = "") -> str:
    """SPATIAL_NEWTON_EULER with ``model``'s numbers, and the slip named (a key of SPATIAL_SLIPS) made."""
    bodies = model.bodies
    text = SPATIAL_NEWTON_EULER.format(
        R0=repr([b.R0.tolist() for b in bodies]), P=repr([b.P.tolist() for b in bodies]),
        m=repr([float(b.mass) for b in bodies]), Pc=repr([b.p_com.tolist() for b in bodies]),
        Ic=repr([b.I_com.tolist() for b in bodies]), g=repr(model.gravity.tolist()))
    for old, new in SPATIAL_SLIPS.get(slip, GRAVITY_PER_LINK if slip == "gravity-per-link" else []):
        assert old in text, old
        text = text.replace(old, new)
    return text
