# Stage 'modal': rules are added by its chapter issue.
