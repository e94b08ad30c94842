"""Jobs: one module per workflow of contactres, each with the same contract.

Every job module (``contactres.jobs.<workflow>``) defines a frozen ``Settings`` dataclass, a
typed ``Result`` (a frozen dataclass of tables and values, each table bound to its schema; see
:class:`contactres.jobs.contract.JobResult`) and

    run(inputs, settings, progress=None) -> Result

The command line is a thin layer over them (options -> ``Settings`` -> ``run`` -> printing), and
the Python API calls the same ``run``::

    >>> from contactres.jobs import qcm_loop
    >>> result = qcm_loop.run(None, qcm_loop.Settings(kappa=1e5, mu=0.5, normal_force=1e-3))
    >>> list(result.tables())
    ['table']

Conventions (:mod:`contactres.jobs.contract`): SI units in the settings and in the tables (each
column name carries its unit); a job never writes a file nor prints (the report writes a Result:
:func:`contactres.report.write_report`); ``progress`` gets one line per stage; a user's
error raises :class:`contactres.errors.ContactresInputError`. The modules are imported when first
used (``from contactres.jobs import dcsf``): this package imports nothing itself.

The jobs: ``contact`` (Hertz contact, normal and tangential stiffness), ``dcsf`` (the DCSF
curve), ``qcm_loop`` (Δf, ΔΓ against the amplitude of a partial-slip contact), ``afm_invert``
and ``rum_invert`` (contact resonances -> k*, modulus), ``qcm_stiffness`` (κ + iωξ against time
from a QCM-D export), ``qcm_particles`` (attached particles: κ, ξ, coverage and the coupled
resonance against time from QCM-D shifts over the overtones), ``qcm_spectra`` (admittance
spectra -> the sweep table), ``qcm_sweeps`` (paper 2's analysis of amplitude sweeps),
``crystals`` (the built-in solids and their moduli), ``maps_synthetic``, ``maps_predict`` and
``maps_fit`` (polycrystal maps; their computations in :mod:`contactres.jobs.maps`), ``paper1``
and ``paper2`` (the numbers of the papers' figures) and ``demo`` (the main workflows on the
bundled data). Shared by them: :mod:`contactres.jobs.maps`
(the map computations) and :mod:`contactres.jobs.readers` (every reader recipe in one registry,
through which the jobs read EBSD exports and value grids).
"""
