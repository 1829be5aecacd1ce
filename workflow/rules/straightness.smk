# Stage 'straightness': rules are added by its chapter issue.
