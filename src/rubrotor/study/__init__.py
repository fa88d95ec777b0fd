"""Studies around the seed reproduction (``rubrotor reproduce``): the seed's own equations
(:mod:`~rubrotor.study.seedform_study`), the robustness of every claim over the assumptions the
seed leaves open (:mod:`~rubrotor.study.robustness`), rub detection with noise
(:mod:`~rubrotor.study.detection`) and their figures (:mod:`~rubrotor.study.figures`).
"""
