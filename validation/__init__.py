"""Validation of the half-space (MDR) contact model against the FE model.

``python -m validation.compare`` runs the scene catalogue (``validation.scenes``)
through both models and writes a report (``validation.report``).
"""
