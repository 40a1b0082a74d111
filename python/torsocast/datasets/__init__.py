"""Readers that turn public datasets into torso pose series (see each module's licence notes)."""
