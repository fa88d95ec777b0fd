"""Force terms: every force the engine applies, one module each."""
