# Stage 'forces': rules are added by its chapter issue.
