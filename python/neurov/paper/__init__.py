"""The paper's experiments (Figs. 3-5), reproduced by ``neurov paper``:
:mod:`neurov.paper.experiments` runs them, :mod:`neurov.paper.figures`
draws them."""
