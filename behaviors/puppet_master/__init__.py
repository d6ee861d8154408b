"""Reactive behaviour by demonstration (Puppet Master, paper 002 sections 4.1-4.4).

A designer demonstrates with two pucks how a reactor responds to a main character; live, the
reactor's motion is generated step by step at 40 Hz from the main's motion, keeping the
demonstrated style. Modules: ``resample`` (fixed generation rate, causal live resampling),
``features`` (4.2), ``similarity`` (4.3: situation similarity, path coherence, balancing),
``generation`` (4.4.1 and the table), ``detail`` (4.4.2 Haar texture), ``step`` (one
generation step: BestMatch in ``step_match``, then Output Generation's stages in ``step``,
``step_detail`` and ``step_senses``), ``engine``
(:class:`~behaviors.puppet_master.engine.Behavior` and
:class:`~behaviors.puppet_master.engine.Reactor`, its pose between steps in ``shown_pose``),
``character`` (the measured constants by which a behaviour reads its character: a still main,
a touch, one that stops with, walks with, keeps away from or charges into its main);
compiled: ``search_kernel`` (the searches), ``step_kernel`` with ``generation_kernel``,
``step_senses_kernel``, ``darts_kernel`` and ``step_math`` (the step, to the Python step's
bits), built by ``kernels``.
"""
