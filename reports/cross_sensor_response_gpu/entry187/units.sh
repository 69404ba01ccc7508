# Sourced by the run scripts of research log entries 187-188 (not run alone): their two parts' units, in order.
# other: other16's 16 units by the fold that holds them out (four to a fold, folds 0-3: the fold is the index
# over 4); fleet: entry 178's 16 units of fleet88 (fold 0's first 16 held-out units).
other=(SIM23-000 SIM23-002 SIM23-013 SIM23-014 SIM23-004 SIM23-008 SIM23-011 SIM23-012
       SIM23-001 SIM23-003 SIM23-006 SIM23-007 SIM23-005 SIM23-009 SIM23-010 SIM23-015)
fleet=(SIM40-001 SIM40-002 SIM40-004 SIM40-005 SIM40-006 SIM40-011 SIM40-014 SIM40-015
       SIM40-020 SIM40-022 SIM40-023 SIM40-024 SIM40-025 SIM40-027 SIM40-032 SIM40-033)
