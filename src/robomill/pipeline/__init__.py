"""The pipeline's own tooling, apart from the science: chapter rendering (``chapters``,
``captions``), the book (``book``), the scorecard (``scorecard``), run logs and the failure
summary (``runlog``, ``failures``), rerun reasons (``why``), notebooks on a run (``explore``),
the artefact catalogue and provenance (``catalog``, ``provenance``), configuration checks
(``config``) and the rules' code inputs (``codedeps``).

The science — calibration, surface, forces, straightness, modal, chatter, stiffness,
beamframe, hexapod, kinematics, spectra, io, synth — lives beside this package in
:mod:`robomill` and imports nothing from it (a test checks this); the package's top level
re-exports :func:`robomill.pipeline.catalog.list_artefacts` for notebooks (looked up lazily).

"""
