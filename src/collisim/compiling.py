"""How one of collisim's kernels is typed when another calls it: by its arguments' types, not
by the values of constants among them.

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
"""
from numba.core import dispatcher, errors, types

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
