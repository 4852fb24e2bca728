"""DNA layer (stand-in package until the lead's layout lands)."""
