"""Resonators that see a contact through a shift of their resonance: the QCM (paper 2)."""
