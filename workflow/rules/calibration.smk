# Stage 'calibration': rules are added by its chapter issue.
