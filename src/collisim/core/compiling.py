"""How collisim's kernels compile, and where numba keeps them: numba as published.

`compiled`: numba.njit(cache=True) for collisim's kernels, in two forms. Compiled code calls the
function as an overload (numba.extending.overload, as numba's own library functions are
written): compiled without the CPython and C wrappers a function needs only to be called from
Python, as numba compiles every overload. Most kernels are called from compiled code alone, and
those wrappers were a large share of a first frame's compiling (docs/benchmarks.md). Called from
Python, the kernel is compiled once more, on that first call, with its wrappers, into a cache
entry of its own (a copy of the function named NAME + FROM_PYTHON: numba keys a cache entry to
the function's name and signature, not to how it was compiled, and an entry without the
wrapper, called from Python, would crash the process).

`kernel`: compiled(error_model="numpy", _nrt=False), for every function that allocates nothing
and returns no array (most of them: whatever a step or an event does per body, pair, row or
ray). Division by zero gives inf or nan as in NumPy, as everywhere in the engine, instead of
raising. `_nrt=False` compiles them without numba's runtime: numba counts a reference to every
array a compiled function is handed, and to every array inside a namedtuple it is handed (the
engine's state travels as namedtuples of arrays), with an atomic increment on entry and a
decrement on return, and a function that does that is seldom inlined by LLVM. Compiled with the
runtime, ccd's event loop ran 6.5 times slower, and the discrete step's pair loop spent two
thirds of its time calling (docs/benchmarks.md). It is numba's own jit option, passed as any
other; it is not in numba's reference pages, which is one reason numba is pinned to the release
range tested (pyproject.toml). Without the runtime numba refuses to compile an allocation, in
the kernel or in anything it calls, which must then be `compiled`; and a kernel must not return
an array (nobody would count that reference): `refuse_arrays_from_kernels` fails such a kernel
as it compiles.

`inlined`: a kernel that LLVM inlines into each compiled caller (numba's forceinline=True): for
the short functions called per event, pair or row that are handed the engine's state (bodies,
rows: namedtuples of arrays), which a call hands over flattened into some two hundred scalar
arguments. Each such function is short and called from one or two places.

`use_cache_folder`: the compiled kernels are kept in a folder named by a digest of every one of
collisim's sources. numba keys a cache entry to the one file that defines the function, yet a
kernel carries the compiled code of every kernel it calls, from other files: after an edit to
one file (or a `git pull` into an editable install) a kernel that calls into it would load its
old code from the cache. A new digest is a new, empty folder: a change anywhere compiles the
kernels again, once. The folder is $NUMBA_CACHE_DIR/collisim-DIGEST when that is set, else
$XDG_CACHE_HOME/collisim/kernels/DIGEST (~/.cache when unset); numba's own setting
(numba.config.CACHE_DIR) points there.

`save_one_process_at_a_time`: processes that compile into that folder at once (two renders on a
fresh install, the test suite's workers) compile side by side, one a core, and take turns only to
save. numba numbers a function's cached entries in the order they are saved: two processes saving
one kernel for two argument types at once could both take number 1, and a later run would load
code compiled for other types. So from the end of each compile (numba's "numba:compile" event,
numba.core.event) until numba lets go of its compiler lock, within which it saves what it
compiled, the process holds a lock on a file in the folder. Two processes that need the same
kernel at the same moment may both compile it; the second save writes the same entry again.
"""
import atexit
import functools
import hashlib
import os
import threading
import types

import numba
from numba import njit
from numba.core import event
from numba.core import types as numba_types
from numba.extending import overload

try:
    import fcntl
except ImportError:   # Windows: no file locks here, so saves do not take turns (and no first-run helper starts)
    fcntl = None

PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # collisim/
FROM_PYTHON = "_from_python"   # the name's suffix of the copy a kernel's calls from Python compile


def compiled(function=None, *, python_runs_it=False, **options):
    """numba.njit(cache=True, **options), compiled without numba's wrappers where compiled code
    calls it, and with them where Python does (the module docstring). As a decorator:
    @compiled or @compiled(option=value, ...). python_runs_it: a call from Python runs the
    function itself, uncompiled (constructor)."""
    if function is None:
        return functools.partial(compiled, python_runs_it=python_runs_it, **options)
    options = dict(cache=True, **options)
    from_python = []   # the dispatcher Python calls, made at the first call
    made = threading.Lock()

    @functools.wraps(function)
    def call_from_python(*args, **kwargs):
        if python_runs_it:
            return function(*args, **kwargs)
        if not from_python:
            with made:
                if not from_python:
                    from_python.append(njit(**options, no_cfunc_wrapper=True)(_copy_named(function, FROM_PYTHON)))
        return from_python[0](*args, **kwargs)

    # what compiled code compiles, and how (compile_for_compiled_code too)
    call_from_python.function = function
    call_from_python.compiled_code_options = dict(options, no_cpython_wrapper=True, no_cfunc_wrapper=True)
    overload(call_from_python, jit_options=call_from_python.compiled_code_options, strict=False)(
        lambda *args, **kwargs: function)
    return call_from_python


def _copy_named(function, suffix: str):
    """function under a name of its own (its cache entries apart from the function's)."""
    copy = types.FunctionType(function.__code__, function.__globals__, function.__name__ + suffix,
                              function.__defaults__, function.__closure__)
    copy.__qualname__ = function.__qualname__ + suffix
    copy.__module__, copy.__kwdefaults__ = function.__module__, function.__kwdefaults__
    return copy


def compile_for_compiled_code(kernel, arguments) -> None:
    """Compile (or load from the cache) `kernel` as compiled code calls it with `arguments`
    (engine/warm.py): into the cache entries its compiled callers load."""
    njit(**kernel.compiled_code_options)(kernel.function).compile(tuple(numba.typeof(a) for a in arguments))


def constructor(function=None, **options):
    """compiled(**options) where compiled code calls it; called from Python, the function runs
    as it is (as numba.extending.register_jitable's functions do). For functions that only make
    arrays with numpy, as fast from Python: a copy compiled for Python would cost a first run
    its compile and nothing else."""
    if function is None:
        return functools.partial(constructor, **options)
    return compiled(function, python_runs_it=True, **options)


def kernel(function):
    """compiled(error_model="numpy", _nrt=False) (the module docstring)."""
    return compiled(function, error_model="numpy", _nrt=False)


class _ArraysFromKernels(event.Listener):
    """Refuses a kernel that returns an array, as it compiles: compiled without numba's runtime,
    it would hand its caller a reference nobody counted, and the array would be freed while still
    in use (the process aborts later, far from the cause, or reads freed memory)."""

    def on_start(self, event_):
        pass

    def on_end(self, event_):
        dispatcher = event_.data["dispatcher"]
        if dispatcher.targetoptions.get("_nrt", True):
            return
        for result in dispatcher.overloads.values():
            if _holds_array(result.signature.return_type):
                raise TypeError(f"kernel {dispatcher.py_func.__qualname__} returns an array "
                                f"({result.signature.return_type}): make it `compiled`")


def _holds_array(numba_type) -> bool:
    if isinstance(numba_type, numba_types.Array):
        return True
    return isinstance(numba_type, numba_types.BaseTuple) and any(_holds_array(t) for t in numba_type)


def refuse_arrays_from_kernels() -> None:
    """Check every kernel numba compiles from now on (_ArraysFromKernels)."""
    event.register("numba:compile", _ArraysFromKernels())


def inlined(function):
    """A kernel inlined by LLVM into every compiled caller (the module docstring)."""
    return compiled(function, error_model="numpy", _nrt=False, forceinline=True)


@functools.lru_cache(maxsize=None)
def package_digest(root: str) -> str:
    """sha256 of every .py file under root (relative paths and contents, in sorted order)."""
    digest = hashlib.sha256()
    for folder, folders, files in os.walk(root):
        folders[:] = sorted(name for name in folders if name != "__pycache__")
        for name in sorted(files):
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                digest.update(os.path.relpath(path, root).encode() + b"\0")
                with open(path, "rb") as file:
                    digest.update(file.read() + b"\0")
    return digest.hexdigest()


def cache_folder(root: str = PACKAGE) -> str:
    """Where the kernels compiled from the sources under root are kept (the module docstring)."""
    digest = package_digest(root)[:20]
    numba_folder = os.environ.get("NUMBA_CACHE_DIR")
    if numba_folder:
        return os.path.join(numba_folder, f"collisim-{digest}")
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "collisim", "kernels", digest)


def use_cache_folder() -> None:
    """Have numba keep the kernels defined from now on in cache_folder(); where that folder
    cannot be made or written, numba keeps its own default."""
    folder = cache_folder()
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return
    if os.access(folder, os.W_OK):
        numba.config.CACHE_DIR = folder


class _SaveLock(event.Listener):
    """Held from the end of a compile until numba has let go of the compiler lock it compiled
    under: the save of what was compiled (the module docstring). One lock file, opened once a
    process and closed at its exit. numba's lock is re-entrant and is announced before it is
    taken and after it is let go, so each thread counts its own depth; the process's threads take
    turns through `threads`, since a file lock is the process's."""

    def __init__(self, path: str):
        self.path, self.file = path, None
        self.threads = threading.Lock()
        self.mine = threading.local()   # per thread: depth in numba's lock, and where the save ends

    def on_start(self, event_):
        if event_.kind == "numba:compiler_lock":
            self.mine.depth = getattr(self.mine, "depth", 0) + 1

    def on_end(self, event_):
        mine = self.mine
        if event_.kind == "numba:compile":   # compiled: numba saves it before it lets go
            if getattr(mine, "release_at", None) is None:
                self.threads.acquire()
                try:
                    if self.file is None:
                        self.file = open(self.path, "a")
                        atexit.register(self.file.close)
                    fcntl.flock(self.file, fcntl.LOCK_EX)   # another process saving: wait for it
                except BaseException:
                    self.threads.release()
                    raise
                mine.release_at = mine.depth - 1
            return
        mine.depth -= 1
        if getattr(mine, "release_at", None) is not None and mine.depth <= mine.release_at:
            mine.release_at = None
            try:
                fcntl.flock(self.file, fcntl.LOCK_UN)
            finally:
                self.threads.release()


def save_one_process_at_a_time() -> None:
    """Take turns with other processes saving into this cache folder (the module docstring);
    nothing where numba keeps its own default folder or files cannot be locked."""
    folder = numba.config.CACHE_DIR
    if fcntl is None or not folder or saves_take_turns():
        return
    lock = _SaveLock(os.path.join(folder, "saving.lock"))
    event.register("numba:compiler_lock", lock)
    event.register("numba:compile", lock)
    save_one_process_at_a_time.listening = True


def saves_take_turns() -> bool:
    """Whether this process's saves into the cache folder take turns with other processes'
    (save_one_process_at_a_time is listening): only then may two processes compile into it."""
    return getattr(save_one_process_at_a_time, "listening", False)
