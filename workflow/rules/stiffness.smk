# Stage 'stiffness': rules are added by its chapter issue.
