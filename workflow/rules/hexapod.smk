# Stage 'hexapod': rules are added by its chapter issue.
