# Stage 'surface': rules are added by its chapter issue.
