"""DNA in a magnetic tweezers: the molecule, models, interactions, hat curves, fits."""
