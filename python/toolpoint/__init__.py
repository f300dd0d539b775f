"""toolpoint: tool point FRFs of spindle–holder–tool assemblies, the dynamics of their joints
(closed-form identification after Özşahin et al. 2009, and a band fit with intervals), and chatter
stability lobes — the C++ library's procedures on numpy arrays.

Conventions (those of pyFBS and SDynPy):

* SI units everywhere (m, kg, N, Pa, s, rad); frequencies in Hz; spindle speeds in rpm.
* Frequencies: float64 arrays of shape (n,).
* A receptance block series [[H, L], [N, P]]: complex128 (n, 2, 2) (H m/N, L 1/N, N rad/N,
  P rad/(N·m)); a single FRF: complex128 (n,); a free–free component's end receptances:
  complex128 (n, 4, 4) over (w1, θ1, w2, θ2).
* Enumerations are lower-case strings ('holder_tool', 'zoa', 'tool', ...), as in the JSON output.
* Results carry their warnings (``.warnings``) and convert to plain data with ``.to_dict()``
  (the keys of the CLI's ``--json``); functions that return bare arrays report warnings as
  ``toolpoint.Warning``.
* Errors are ``toolpoint.Error`` subclasses — InvalidArgument, InputError, NumericalError,
  VerdictFailure, IoError — with the library's message (``str(e)``) and fix (``e.hint``).
* Long computations release the GIL: other Python threads run meanwhile. ``progress=callable``
  receives the fraction done.

Example::

    import toolpoint as tp
    a = tp.load_assembly("examples/bt40_shrinkfit_16mm.toml").assembly
    p = tp.run_prediction_study(a)                # SHT11 on the assembly's grid
    H = p.frf[:, 0, 0]                            # tool point H [m/N], complex (n,)
    print([round(m.frequency_hz, 1) for m in p.modes])
"""

from ._toolpoint import *  # noqa: F401,F403  (the bindings: every public name)
from ._toolpoint import (  # noqa: F401  (named for readers and linters)
    Error,
    InputError,
    InvalidArgument,
    IoError,
    NumericalError,
    VerdictFailure,
    Warning,
    __version__,
)
from . import _toolpoint as _ext
import inspect as _inspect

__all__ = [name for name in dir(_ext) if not name.startswith("_")] + ["__version__"]


def _short(value, depth=0):
    """A value of to_dict() in a few characters: numbers to 5 significant digits, long lists and
    nested dicts by their size, so a result's repr fits on a line or two."""
    if isinstance(value, float):
        return f"{value:.5g}"
    if isinstance(value, str):
        return repr(value if len(value) <= 40 else value[:37] + "...")
    if isinstance(value, list):
        if len(value) <= 4 and all(isinstance(v, (int, float)) for v in value):
            return "[" + ", ".join(_short(v) for v in value) + "]"
        return f"[{len(value)} items]"
    if isinstance(value, dict):
        if depth > 0 or len(value) > 4:
            return "{" + f"{len(value)} keys" + "}"
        return "{" + ", ".join(f"{k}: {_short(v, depth + 1)}" for k, v in value.items()) + "}"
    return repr(value)


def _repr_from_dict(self):
    """ClassName(key=value, ...) from the result's to_dict(): its scalar fields first, lists and
    nested objects by size, at most 8 fields; ``.to_dict()`` has everything."""
    try:
        d = self.to_dict()
    except Exception:  # a result that cannot convert still gets a repr
        return f"<toolpoint.{type(self).__name__}>"
    if not isinstance(d, dict):
        return f"<toolpoint.{type(self).__name__}>"
    keys = sorted(d, key=lambda k: isinstance(d[k], (list, dict)))
    parts = [f"{k}={_short(d[k])}" for k in keys[:8]]
    more = f", … {len(keys) - 8} more" if len(keys) > 8 else ""
    return f"{type(self).__name__}({', '.join(parts)}{more})"


for _name in dir(_ext):
    _cls = getattr(_ext, _name)
    if isinstance(_cls, type) and hasattr(_cls, "to_dict") and "__repr__" not in _cls.__dict__:
        try:
            _cls.__repr__ = _repr_from_dict
        except (AttributeError, TypeError):  # a type that does not take attributes keeps its repr
            pass


def _options_type(cls):
    """A bound *Options struct (its ``_fields``, from C++): keyword-only construction with the C++
    defaults (read from a default instance, so they cannot drift), and a repr of every field."""
    base_init = cls.__init__
    fields = tuple(cls._fields)
    default = cls()
    P = _inspect.Parameter
    params = [P("self", P.POSITIONAL_ONLY)] + [P(f, P.KEYWORD_ONLY, default=getattr(default, f)) for f in fields]

    def __init__(self, **kwargs):
        unknown = sorted(set(kwargs) - set(fields))
        if unknown:
            raise TypeError(f"{cls.__name__}() got unexpected keyword argument(s) {', '.join(unknown)}; "
                            f"its fields: {', '.join(fields)}")
        base_init(self)
        for name, value in kwargs.items():
            setattr(self, name, value)

    __init__.__signature__ = _inspect.Signature(params)
    __init__.__doc__ = f"{cls.__name__}(*, {', '.join(f'{f}={getattr(default, f)!r}' for f in fields)})"
    cls.__init__ = __init__
    cls.__repr__ = lambda self: f"{cls.__name__}({', '.join(f'{f}={getattr(self, f)!r}' for f in fields)})"
    cls.__eq__ = lambda self, other: type(other) is cls and all(getattr(self, f) == getattr(other, f) for f in fields)
    cls.__hash__ = None


for _name in dir(_ext):
    _cls = getattr(_ext, _name)
    if isinstance(_cls, type) and "_fields" in _cls.__dict__:
        _options_type(_cls)
