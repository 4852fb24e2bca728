"""Unit-aware DNA layer (stand-in package until the domain layout lands on main)."""
