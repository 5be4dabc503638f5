package telerehab;

import ca.uhn.fhir.context.FhirContext;
import ca.uhn.fhir.context.support.DefaultProfileValidationSupport;
import ca.uhn.fhir.validation.FhirValidator;
import ca.uhn.fhir.validation.SingleValidationMessage;
import ca.uhn.fhir.validation.ValidationResult;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.HashMap;
import java.util.Map;
import ca.uhn.fhir.context.support.IValidationSupport;
import org.hl7.fhir.instance.model.api.IBaseResource;
import org.hl7.fhir.common.hapi.validation.support.CommonCodeSystemsTerminologyService;
import org.hl7.fhir.common.hapi.validation.support.InMemoryTerminologyServerValidationSupport;
import org.hl7.fhir.common.hapi.validation.support.PrePopulatedValidationSupport;
import org.hl7.fhir.common.hapi.validation.support.SnapshotGeneratingValidationSupport;
import org.hl7.fhir.common.hapi.validation.support.ValidationSupportChain;
import org.hl7.fhir.common.hapi.validation.validator.FhirInstanceValidator;
import org.hl7.fhir.r4.model.Bundle;
import org.hl7.fhir.r4.model.CodeSystem;
import org.hl7.fhir.r4.model.Questionnaire;
import org.hl7.fhir.r4.model.Resource;

/**
 * Validates FHIR R4 JSON files with HAPI FHIR's instance validator against R4 core, offline
 * (no terminology server: UCUM and the small HL7 code systems are checked in memory, LOINC and
 * SNOMED CT are not known). The CodeSystems and Questionnaires a Bundle carries are known to the
 * validator, so that its codes and its QuestionnaireResponses are checked against them.
 *
 * <p>Prints one line a message, {@code SEVERITY<TAB>messageId<TAB>location<TAB>text}, then
 * {@code errors=N warnings=N information=N} a file. Exit status 0 unless a file cannot be read
 * or parsed (2); the caller judges the messages.
 */
public final class Validate {
    private Validate() {}

    /** The questionnaires of a bundle by canonical URL (a `|version` suffix ignored). */
    private record Questionnaires(FhirContext ctx, Map<String, Questionnaire> byUrl)
            implements IValidationSupport {
        @Override
        public FhirContext getFhirContext() {
            return ctx;
        }

        @Override
        @SuppressWarnings("unchecked")
        public <T extends IBaseResource> T fetchResource(Class<T> type, String uri) {
            if (uri == null || (type != null && !type.isAssignableFrom(Questionnaire.class))) {
                return null;
            }
            int bar = uri.indexOf('|');
            return (T) byUrl.get(bar < 0 ? uri : uri.substring(0, bar));
        }
    }

    public static void main(String[] args) throws Exception {
        if (args.length == 0) {
            System.err.println("usage: Validate BUNDLE.json...");
            System.exit(2);
        }
        FhirContext ctx = FhirContext.forR4();
        for (String arg : args) {
            String text = Files.readString(Path.of(arg), StandardCharsets.UTF_8);
            PrePopulatedValidationSupport own = new PrePopulatedValidationSupport(ctx);
            Map<String, Questionnaire> questionnaires = new HashMap<>();
            Resource parsed = (Resource) ctx.newJsonParser().parseResource(text);
            if (parsed instanceof Bundle bundle) {
                for (Bundle.BundleEntryComponent e : bundle.getEntry()) {
                    Resource r = e.getResource();
                    if (r instanceof CodeSystem cs) {
                        own.addCodeSystem(cs);
                    } else if (r instanceof Questionnaire q) {
                        questionnaires.put(q.getUrl(), q);
                    }
                }
            }
            ValidationSupportChain chain = new ValidationSupportChain(
                    new DefaultProfileValidationSupport(ctx),
                    own,
                    new Questionnaires(ctx, questionnaires),
                    new CommonCodeSystemsTerminologyService(ctx),
                    new InMemoryTerminologyServerValidationSupport(ctx),
                    new SnapshotGeneratingValidationSupport(ctx));
            FhirValidator validator = ctx.newValidator()
                    .registerValidatorModule(new FhirInstanceValidator(chain));
            ValidationResult result = validator.validateWithResult(text);
            int errors = 0;
            int warnings = 0;
            int information = 0;
            for (SingleValidationMessage m : result.getMessages()) {
                switch (m.getSeverity()) {
                    case ERROR, FATAL -> errors++;
                    case WARNING -> warnings++;
                    default -> information++;
                }
                System.out.println(m.getSeverity() + "\t" + m.getMessageId() + "\t"
                        + m.getLocationString() + "\t" + m.getMessage().replace('\n', ' '));
            }
            System.out.println("errors=" + errors + " warnings=" + warnings
                    + " information=" + information);
        }
    }
}
