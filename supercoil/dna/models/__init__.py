"""DNA models (stand-in until the lead's model interface lands on main)."""
