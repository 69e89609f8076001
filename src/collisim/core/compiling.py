"""How collisim's kernels compile.

`plain_constants`: a kernel is typed, when another calls it, by its arguments' types, not by the
values of constants among them.

numba types an integer constant (a module constant such as PAIR or a phase number, a literal
-1) as Literal[int](value), and a compiled function called from compiled code is compiled once
per distinct argument types, those literal values included. So `_lap(cycles, BROAD, t)` and
`_lap(cycles, NARROW, t)` were two compiles of the same code (seven for `_lap`, five for the
event log's `append`, two to four for the solver's and ccd's helpers): a cold first run spent a
third of its compiling on copies. numba's own overloads already prefer the plain types and fall
back to the literal ones only when typing with the plain ones fails
(numba.core.types.functions.Function.get_call_type); its dispatchers do not. `plain_constants`
gives collisim's dispatchers that same policy, in this one place rather than at every call site.

The bytes are the same: LLVM still sees the constant once a caller inlines its callee, and
without fastmath it folds floating point exactly as it computes it at run time.

`uncounted`: the kernels run at every event or contact are compiled without numba's reference
counting, which cost more than their arithmetic (see there). Small helpers handed arrays are
uncounted too, rather than inlined by numba (inline="always"), which types and compiles a
helper again inside every caller (the same bytes; a cold first run of particles_250 under
discrete took 84-90 CPU seconds against 89-90 inlined, alternating runs on a loaded machine).

`inlined`: uncounted, and inlined by LLVM into its callers. numba hands a namedtuple of arrays
to a compiled function as a few hundred scalar arguments; the event loop's functions that are
handed the engine's state at every event are inlined rather than called (see there).

`stamp_with_package`: a cached kernel is stale when any of collisim's sources changes, not only
its own file. numba keys a cache entry to the hash of the one file that defines the function,
yet a kernel carries the compiled code of every kernel it calls, from other files: after an
edit to response/statics.py (or a `git pull` into an editable install) run_frames kept loading
the old wall response from its cache. So every collisim kernel's cache stamp also holds a
digest of all the package's sources: a change anywhere compiles the kernels again, once.

`name_entries_by_key`: processes that compile at once (two renders on a fresh install, the test
suite's workers) never leave a cache index pointing at code compiled for other argument types.
"""
import functools
import hashlib
import os

from numba import njit
from numba.core import dispatcher, errors, types
from numba.core.compiler import CompilerBase, DefaultPassBuilder
from numba.core.compiler_machinery import FunctionPass, register_pass
from numba.core.lowering import Lower
from numba.core.typed_passes import NativeLowering, NopythonTypeInference

OWN_MODULES = "collisim."


def plain_constants() -> None:
    """Type calls between collisim's compiled functions with plain types first (idempotent)."""
    if getattr(dispatcher.Dispatcher.get_call_template, "plain_constants", False):
        return
    by_literals = dispatcher.Dispatcher.get_call_template

    def get_call_template(self, args, kws):
        if self.py_func.__module__.startswith(OWN_MODULES):
            plain_args = tuple(types.unliteral(a) for a in args)
            plain_kws = {key: types.unliteral(value) for key, value in kws.items()}
            if plain_args != tuple(args) or plain_kws != kws:
                try:
                    return by_literals(self, plain_args, plain_kws)
                except errors.TypingError:
                    pass   # a callee that needs a constant (a tuple index, a pruned branch) gets it
        return by_literals(self, args, kws)

    get_call_template.plain_constants = True
    dispatcher.Dispatcher.get_call_template = get_call_template


PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))   # collisim/: the sources whose kernels are stamped


@functools.lru_cache(maxsize=None)
def package_digest(root: str) -> str:
    """sha256 of every .py file under root (relative paths and contents, in sorted order), read
    once a process (5 ms)."""
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


def stamp_with_package() -> None:
    """Stamp the cache entries of collisim's kernels with package_digest as well as numba's
    per-file stamp (see the module docstring); other code's entries are left as they are
    (idempotent)."""
    from numba.core import caching

    impl = getattr(caching, "CacheImpl", None) or caching._CacheImpl   # numba >= 0.61, and before
    if getattr(impl, "collisim_stamped", False):
        return

    def stamped(locator):
        class PackageStamped(locator):
            def get_source_stamp(self):
                stamp = super().get_source_stamp()
                inside = os.path.abspath(self._py_file).startswith(PACKAGE + os.sep)
                return (stamp, package_digest(PACKAGE)) if inside else stamp
        PackageStamped.__name__ = PackageStamped.__qualname__ = f"PackageStamped{locator.__name__}"
        return PackageStamped

    impl._locator_classes = [stamped(locator) if issubclass(locator, caching._SourceFileBackedLocatorMixin)
                             else locator for locator in impl._locator_classes]
    impl.collisim_stamped = True


def _stamped(source_stamp) -> bool:
    """Is this a cache stamp of a collisim kernel (stamp_with_package's)?"""
    return (isinstance(source_stamp, tuple) and len(source_stamp) == 2
            and source_stamp[1] == package_digest(PACKAGE))


def _described(key) -> str:
    """A cache key as text that is the same in every process: numba types by class and name,
    and a named tuple's by its class's full name too (their pickles hold a number each process
    assigns in its own order)."""
    if isinstance(key, types.Type):
        named = getattr(key, "instance_class", None)
        where = f"{named.__module__}.{named.__qualname__}:" if named is not None else ""
        return f"{type(key).__name__}<{where}{key}>"
    if isinstance(key, tuple):
        return "(" + ", ".join(_described(part) for part in key) + ")"
    return repr(key)


def name_entries_by_key() -> None:
    """Name the data file of each cached overload of a collisim kernel after its key (the
    argument types, the machine, the bytecode), and write it before the index that points at it
    (idempotent; other code's caches are left as numba keeps them).

    Why: numba numbers a function's data files in the order its overloads are saved, and writes
    the index first. Two processes compiling one kernel for two argument types at once can both
    take number 1; the index the one writes may then point at the code the other compiled, and
    a later run would load code compiled for other types. A name drawn from the key is never
    another key's. The index is still written whole by whichever process writes it last, so
    the other's entry may be lost: its kernel then compiles again on a later run, correctly."""
    from numba.core import caching

    files = caching.IndexDataCacheFile
    if getattr(files, "collisim_keyed", False):
        return
    numbered = files.save

    def save(self, key, data):
        if not _stamped(self._source_stamp):
            return numbered(self, key, data)
        digest = hashlib.sha256(_described(key).encode()).hexdigest()[:20]
        name = self._data_name_pattern.replace("{number:d}", digest)
        self._save_data(name, data)
        overloads = self._load_index()
        if overloads.get(key) != name:
            overloads[key] = name
            self._save_index(overloads)

    files.save = save
    files.collisim_keyed = True


@register_pass(mutates_CFG=False, analysis_only=True)
class _ReturnsNoArray(FunctionPass):
    """Refuse, once types are known, an uncounted function that returns an array (see uncounted)."""
    _name = "collisim_returns_no_array"

    def __init__(self):
        FunctionPass.__init__(self)

    def run_pass(self, state):
        if _holds_an_array(state.return_type):
            raise errors.TypingError(f"{state.func_id.func_qualname} is compiled without reference counting "
                                     f"(collisim.core.compiling.uncounted) and may not return an array: it returns "
                                     f"{state.return_type}")
        return False


def _holds_an_array(typ) -> bool:
    if isinstance(typ, types.Array):
        return True
    return isinstance(typ, types.BaseTuple) and any(_holds_an_array(t) for t in typ.types)


def _uncounted_pipeline(state):
    """numba's nopython pipeline with _ReturnsNoArray after type inference (not finalized)."""
    pipeline = DefaultPassBuilder.define_nopython_pipeline(state)
    pipeline.add_pass_after(_ReturnsNoArray, NopythonTypeInference)
    return pipeline


class _UncountedCompiler(CompilerBase):
    """numba's nopython pipeline with _ReturnsNoArray after type inference."""

    def define_pipelines(self):
        pipeline = _uncounted_pipeline(self.state)
        pipeline.finalize()
        return [pipeline]


class _AlwaysInlinedLower(Lower):
    """numba's lowering, which also asks LLVM to inline the function into every caller."""

    def lower_normal_function(self, fndesc):
        super().lower_normal_function(fndesc)
        self.function.attributes.add("alwaysinline")


@register_pass(mutates_CFG=True, analysis_only=False)
class _AlwaysInlinedLowering(NativeLowering):
    """numba's native lowering pass, with _AlwaysInlinedLower."""
    _name = "collisim_always_inlined_lowering"

    @property
    def lowering_class(self):
        return _AlwaysInlinedLower


class _InlinedCompiler(CompilerBase):
    """_UncountedCompiler's pipeline, lowered by _AlwaysInlinedLowering instead of NativeLowering."""

    def define_pipelines(self):
        pipeline = _uncounted_pipeline(self.state)
        pipeline.add_pass_after(_AlwaysInlinedLowering, NativeLowering)
        pipeline.passes = [(kind, name) for kind, name in pipeline.passes if kind is not NativeLowering]
        pipeline.finalize()
        return [pipeline]


def uncounted(function):
    """numba.njit(cache=True, error_model="numpy"), compiled without numba's reference counting
    (its runtime, NRT): for functions run at every event or contact that allocate nothing and
    return no array.

    Why: numba counts references to every array a compiled function is handed, and to every
    array inside a namedtuple it is handed (the engine's state travels as namedtuples of
    arrays), with an atomic increment on entry and a decrement on return. LLVM removes the pairs
    only when nothing in between may raise or allocate. The event loop's functions are handed
    up to five such tuples, 40 arrays: measured with perf, the increments and decrements were
    over half of the event loop's time. A function compiled without the runtime emits none.

    What it may not do, refused at compile time: allocate an array (np.empty and friends do not
    type without the runtime), or return an array, even one it was handed (numba would allow
    that, and the caller would then own a reference nobody counted; _ReturnsNoArray refuses it).
    The functions it calls are compiled without reference counting too, so none can hand it a
    new array either (numba refuses one that would).
    Division by zero gives inf or nan as in NumPy (error_model="numpy"), as everywhere in the
    engine."""
    return njit(cache=True, error_model="numpy", _nrt=False, pipeline_class=_UncountedCompiler)(function)


def inlined(function):
    """uncounted, and inlined by LLVM into every compiled caller: for the event loop's functions
    that are handed the engine's state (several namedtuples of arrays) and run at every event.

    Why: numba passes a namedtuple of arrays to a compiled function as its fields flattened into
    scalars, seven to nine for each array, so Bodies, CellGrid and EventQueue together are over
    200 arguments a call; LLVM inlines a callee only when it is small, and these are not. The
    calls that remained were about a third of the event loop's time: measured on the dense gas
    (n = 1 000, 10 s), the loop ran at 8.2e5 events per second with them as calls and at
    1.1-1.2e6 with them inlined, the same events to the bit. Each such function is short and called from one
    or two places, so the code LLVM optimizes grows little. Leaf functions handed only numbers
    (geometry/toi.py) stay calls: inlining time_to_point into the candidate loop made it slower."""
    return njit(cache=True, error_model="numpy", _nrt=False, pipeline_class=_InlinedCompiler)(function)
