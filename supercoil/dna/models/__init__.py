"""DNA models (stand-in package until the lead's registry lands)."""
