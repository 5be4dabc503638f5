# The hub's refusals in the console's language (crates/hub/console/api.js refusalWords).

## The hub's refusals in the console's language (api.js refusalWords): the hub's own words,
## which name the field or the thing refused, follow in English where they add something.

api-error-400 = The hub did not accept this.
api-error-401 = Not signed in, or a wrong e-mail or password.
api-error-403 = Only a clinic administrator can do this.
api-error-404 = Not found. It may have been removed.
api-error-409 = This conflicts with what the hub holds.
api-error-413 = This is too large for the hub.
api-error-415 = The hub did not understand this request.
api-error-422 = Refused: outside the allowed values or the safety bounds.
api-error-429 = Too many tries. Try again in { $seconds } s.
api-error-503 = The hub is busy. Try again in { $seconds } s.
api-error-other = Something went wrong on the hub. Its log has the details.
api-error-detail = { $lead } The hub says: { $detail }
