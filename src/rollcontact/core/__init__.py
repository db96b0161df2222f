"""What every geometry shares: input checks (:mod:`.checks`), the material (:mod:`.materials`), friction laws
(:mod:`.friction`), the method contract (:mod:`.method`), the dispatch engine (:mod:`.dispatch`) and the discretised
elastic half-space (:mod:`.halfspace`).  Nothing here imports a geometry."""
