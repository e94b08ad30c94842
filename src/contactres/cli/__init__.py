"""The ``contactres`` command line (click). Argument parsing and printing only.

Each module here registers its subcommands on :data:`main` when imported.
"""

from . import afm_invert as _afm_invert  # noqa: F401  (registers afm invert)
from . import afm_map as _afm_map  # noqa: F401  (registers afm map)
from . import contact as _contact  # noqa: F401  (registers contact)
from . import crystals as _crystals  # noqa: F401  (registers crystals)
from . import dcsf as _dcsf  # noqa: F401  (registers dcsf)
from . import demo as _demo  # noqa: F401  (registers demo)
from . import examples as _examples  # noqa: F401  (registers examples)
from . import figures_paper1 as _figures_paper1  # noqa: F401  (figures paper1)
from . import figures_paper2 as _figures_paper2  # noqa: F401  (figures paper2)
from . import maps as _maps  # noqa: F401  (registers maps synthetic|predict|fit)
from . import qcm_analyze as _qcm_analyze  # noqa: F401  (registers qcm analyze)
from . import qcm_loop as _qcm_loop  # noqa: F401  (registers qcm loop)
from . import qcm_particles as _qcm_particles  # noqa: F401  (registers qcm particles)
from . import qcm_spectra as _qcm_spectra  # noqa: F401  (registers qcm spectra)
from . import qcm_stiffness as _qcm_stiffness  # noqa: F401  (registers qcm stiffness)
from . import rum_invert as _rum_invert  # noqa: F401  (registers rum invert)
from ._app import main

__all__ = ["main"]
