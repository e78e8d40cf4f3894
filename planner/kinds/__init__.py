"""Scenario kinds: one module per kind, each with ``Config`` and ``run(config, ctx)``.

``Config`` subclasses :class:`planner.scenario.ScenarioBase` with
``kind: Literal["<name>"]``; ``run`` returns a :class:`planner.results.RunResult`.
Modules here are discovered automatically (see :func:`planner.scenario.kinds`); keep their
top-level imports light and import heavy dependencies inside ``run``.
"""
