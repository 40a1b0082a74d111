"""Forecasting evaluations: protocols, metrics, the methods compared, and the reports."""
