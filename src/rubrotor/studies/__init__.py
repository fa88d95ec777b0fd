"""Studies built on the package: the seed paper's reproduction (:mod:`rubrotor.studies.seed`)
and dry whirl and whip (:mod:`rubrotor.studies.dry_whirl`)."""
