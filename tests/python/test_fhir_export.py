"""The FHIR R4 export of a patient (issue 32, `GET /api/patients/{id}/fhir`) validated by an
independent FHIR implementation: the `fhir.resources` models (pydantic, generated from the
HL7 specification; its R4B package, which for every resource type exported here — Bundle,
Patient, CarePlan, ServiceRequest, Observation, CodeSystem — has the same elements as R4).
A clinic of one patient with three simulated sessions, a regimen and a Fugl-Meyer score.
crates/hub/tests/fhir_validator.rs judges the export with the reference validator (HAPI FHIR)."""

from fhir.resources.R4B import get_fhir_model_class
from fhir.resources.R4B.bundle import Bundle

from test_console_browser import VALID, browser, clinic, wait  # noqa: F401 (fixtures)
from test_console_words import log_in, run_session


def call(d, method, path, body=None):
    """`method path` with the page's login and a JSON body: [status, content type, JSON]."""
    return d.execute_async_script(
        "const [method, path, body, done] = arguments;"
        "const init = {method, credentials: 'same-origin', headers: {'Content-Type': 'application/json'}};"
        "if (body !== null) init.body = JSON.stringify(body);"
        "fetch(path, init).then(async r => done([r.status, r.headers.get('content-type'),"
        " await r.text().then(t => (t ? JSON.parse(t) : null))]));", method, path, body)


def test_a_patients_fhir_bundle_of_three_sessions_validates_resource_by_resource(clinic, browser):
    for seed in (2, 3, 4):
        run_session(clinic, "sine-road", seed)
    d = browser
    log_in(d, clinic)
    d.find_element("link text", "P-0042").click()
    wait(d, lambda d: len(d.current_url.split("#/patients/")) == 2)
    patient = d.current_url.split("#/patients/")[1].split("/")[0]
    status, _, _ = call(d, "PUT", f"/api/patients/{patient}/regimen", {"toml": "sessions_per_week = 4\n" + VALID})
    assert status == 200
    status, _, _ = call(d, "POST", f"/api/patients/{patient}/scales",
                        {"scale": "fugl_meyer_ue", "assessed_on": "2026-01-05", "score": 34})
    assert status == 201
    status, kind, bundle = call(d, "GET", f"/api/patients/{patient}/fhir")
    assert status == 200 and kind.startswith("application/fhir+json"), (status, kind)

    # The whole bundle, then every resource alone, by its own model.
    Bundle.model_validate(bundle)
    kinds = []
    for entry in bundle["entry"]:
        resource = entry["resource"]
        model = get_fhir_model_class(resource["resourceType"])
        model.model_validate(resource)
        kinds.append(resource["resourceType"])
    assert kinds.count("Patient") == 1 and kinds.count("CarePlan") == 1 and kinds.count("ServiceRequest") == 1
    assert kinds.count("Observation") == 7, "three sessions, their exercise durations, one scale"
    assert kinds.count("CodeSystem") == 3 and kinds.count("Questionnaire") == 1
    assert kinds.count("Device") == 1, "one station"
    # Every component's code is defined, with its unit, in the bundle's own code system.
    # The hub's codes at the clinic's address (hub.toml's fhir_base; here the default of the
    # hub's name), never a placeholder.
    systems = {r["name"]: r for r in (e["resource"] for e in bundle["entry"]) if r["resourceType"] == "CodeSystem"}
    assert systems["TelerehabMeasures"]["url"].endswith("/fhir/CodeSystem/measures")
    assert "telerehab.example" not in str(bundle)
    measures = {c["code"]: c for c in systems["TelerehabMeasures"]["concept"]}
    sessions = [e["resource"] for e in bundle["entry"]
                if e["resource"]["resourceType"] == "Observation" and "component" in e["resource"]
                and e["resource"]["code"]["coding"][0]["code"] == "session"]
    assert len(sessions) == 3
    for observation in sessions:
        for component in observation["component"]:
            code = component["code"]["coding"][0]["code"]
            assert measures[code]["definition"], code
            assert measures[code]["property"][0]["valueCode"] == component["valueQuantity"]["code"], code
    patient_resource = next(e["resource"] for e in bundle["entry"] if e["resource"]["resourceType"] == "Patient")
    assert set(patient_resource) == {"resourceType", "id", "language", "text", "identifier", "active"}, "pseudonymous only"
    # In the logged-in therapist's language (the browser's here: English), each resource saying so.
    assert patient_resource["language"] == "en" and 'lang="en"' in patient_resource["text"]["div"]
    assert patient_resource["identifier"][0]["value"] == "P-0042"
    print(f"FHIR: {len(kinds)} resources validated by fhir.resources (R4B models), "
          f"{sum(len(o['component']) for o in sessions)} session measures")
