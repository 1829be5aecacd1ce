# Stage 'chatter': rules are added by its chapter issue.
