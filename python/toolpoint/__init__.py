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
    p = tp.run_prediction(a)                      # SHT11 on the assembly's grid
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

__all__ = [name for name in dir(_ext) if not name.startswith("_")] + ["__version__"]
