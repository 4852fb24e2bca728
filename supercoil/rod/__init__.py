"""Elastic rods twisted and slacked: smooth, rough, designed and twist-spun double helices."""
