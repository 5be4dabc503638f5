# The measures spreadsheet's words (crates/hub-care/src/sheet_words.rs): its first header line
# and its words for people; the second header line keeps the technical names.

sheet-col-patient = Patient
sheet-col-session = Session reference
sheet-col-started-local = Started (local time, { $zone })
sheet-col-started-utc = Started (UTC)
sheet-col-exercises = Exercises
sheet-col-ended = How it ended
sheet-col-as-prescribed = Ran as prescribed
sheet-col-pain = Pain after (0–10)
sheet-col-effort = Effort after (Borg CR10 0–10)
sheet-col-felt = How hard it felt
sheet-yes = yes
sheet-no = no

# The standard assessment's spreadsheet (crates/hub/src/web/assessment_sheet.rs): one row a
# measure of a part of an assessment.
sheet-assessment-col-protocol = Protocol version
sheet-assessment-col-seed = Seed of the target steps
sheet-assessment-col-part-key = Part (code)
sheet-assessment-col-part = Part
sheet-assessment-col-measure-key = Measure (code)
sheet-assessment-col-measure = Measure
sheet-assessment-col-value = Value
sheet-assessment-col-unit = Unit
