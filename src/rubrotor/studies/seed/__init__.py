"""Studies around the seed reproduction (``rubrotor reproduce``): the seed's own equations
(:mod:`~rubrotor.studies.seed.seedform_study`), the robustness of every claim over the assumptions the
seed leaves open (:mod:`~rubrotor.studies.seed.robustness`), rub detection with noise
(:mod:`~rubrotor.studies.seed.detection`) and their figures (:mod:`~rubrotor.studies.seed.figures`).
"""
