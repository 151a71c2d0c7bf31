"""The quantities' table, kept here for the importers of old: it lives in `records.quantities`
(the bottom layer, where the extraction reads it)."""

from records.quantities import (GATED_QUANTITIES, QUANTITIES, Quantity, characteristics, derived_values,
                                gated_quantities, readable, reference_values)

__all__ = ["GATED_QUANTITIES", "QUANTITIES", "Quantity", "characteristics", "derived_values", "gated_quantities",
           "readable", "reference_values"]
