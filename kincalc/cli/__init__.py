"""The command line (layer ``cli``): one thin module per command (:mod:`~.fk`,
:mod:`~.ik`, :mod:`~.reach`, ...), the shared option types and the pose-option bundle
(:mod:`~.common`, :mod:`~.targets`), rendering of tables (:mod:`~.render`), ``--batch``
(:mod:`~.batch`) and the lazy command table (:mod:`~.main`). The only room that imports
typer, rich or click; it may use every room below it.
"""
