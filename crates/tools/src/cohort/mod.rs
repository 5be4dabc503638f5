//! `telerehab hub cohort`: the standard assessment's measurement noise, measured on a
//! simulated cohort (issue 42, "real change told from noise").
//!
//! A fresh clinic (SQLite in its directory, or the empty PostgreSQL database `--db` names)
//! served by a `telerehab hub serve` child process; two cohorts of `--patients` unchanged
//! patients each (module `model`: impairment mild to severe, day-to-day variation from published
//! test–retest studies), the first to measure the noise (seed `--seed`), the second held out
//! to test it (seed `--seed` + 1). Every patient's station pairs and runs `--weeks` weekly
//! sessions as `telerehab run --sim --headless --speed max` (module `stations`), the assessment
//! due each week; the sessions reach the hub over the real link. Then, from the hub's
//! database (module `noise`):
//!
//! - every (part, measure)'s ICC(2,1), SEM and MDC95 on the first cohort, printed beside the
//!   published figure where one exists;
//! - the held-out cohort's verdicts, each later week against the first: better or worse only
//!   beyond the first cohort's MDC95. Their truth did not change, so every such verdict is
//!   false; MDC95 is the 95 % band of a difference of two measurements, so about 5 % of them
//!   are expected by construction (fewer where a measure's noise has heavier tails than a
//!   normal's, more where it varies with the patient);
//! - `--write-noise` writes `metrics::assessment_noise`'s table, `--doc` the reliability page
//!   (module `report`), and every cohort patient's FHIR bundle goes into the clinic's directory
//!   (`fhir/`), kept with `--keep`.

mod model;
mod noise;
mod report;
mod stations;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, bail};

use crate::chaos::hubs::{Hub, HubSpec};
use noise::Occasions;
use stations::Station;

/// `telerehab hub cohort`.
#[derive(Debug, Clone, clap::Args)]
pub struct CohortArgs {
    /// Simulated patients in each of the two cohorts (measured and held out).
    #[arg(long, default_value_t = 20)]
    pub patients: usize,
    /// Weekly assessments per patient, 2 to 50 (the station keeps 50 in its history).
    #[arg(long, default_value_t = 8)]
    pub weeks: usize,
    /// Seed of the measured cohort (the held-out cohort's is this + 1).
    #[arg(long, default_value_t = 42)]
    pub seed: u64,
    /// An empty PostgreSQL database for the clinic (`postgres://…`); default SQLite in the
    /// clinic's directory.
    #[arg(long, value_name = "URL")]
    pub db: Option<String>,
    /// Keep the clinic, the stations' homes, their logs and the FHIR bundles here (default: a
    /// temporary directory, removed).
    #[arg(long, value_name = "DIR")]
    pub keep: Option<PathBuf>,
    /// Write the noise table (default the compiled-in one,
    /// `crates/metrics/data/assessment-noise-v1.json`, from the sources' top directory).
    #[arg(long, value_name = "FILE", num_args = 0..=1,
          default_missing_value = "crates/metrics/data/assessment-noise-v1.json")]
    pub write_noise: Option<PathBuf>,
    /// Write the reliability page (Markdown), e.g. `docs/RELIABILITY.md`.
    #[arg(long, value_name = "FILE")]
    pub doc: Option<PathBuf>,
    /// Stations running at once.
    #[arg(long, default_value_t = 2)]
    pub jobs: usize,
}

/// A cohort patient at the clinic.
#[derive(Debug, Clone)]
struct Enrolled {
    cohort_seed: u64,
    index: usize,
    pseudonym: String,
    patient_id: String,
    code: String,
    patient: model::Patient,
}

/// Runs the cohort and reports; an error if a station failed or a result is missing.
pub async fn run(args: CohortArgs) -> anyhow::Result<()> {
    // A week is seen by the station's history growing by one line; the history keeps
    // `assessment::KEPT` lines, so a cohort runs no more weeks than that.
    let max_weeks = session::assessment::KEPT;
    if !(2..=200).contains(&args.patients) || !(2..=max_weeks).contains(&args.weeks) {
        bail!("--patients must be 2 to 200 and --weeks 2 to {max_weeks}");
    }
    if !(1..=32).contains(&args.jobs) {
        bail!("--jobs must be 1 to 32");
    }
    let started = std::time::Instant::now();
    let tmp = tempfile::tempdir().context("cannot make the cohort's directory")?;
    let dir = args.keep.clone().unwrap_or_else(|| tmp.path().to_owned());
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot make {}", dir.display()))?;
    let clinic_dir = dir.join("clinic");
    let cohort = enrol(&args, &clinic_dir).await?;
    println!(
        "hub cohort: 2 cohorts of {} simulated patients × {} weekly assessments (seeds {} and {}), \
         {} stations at once, clinic in {}",
        args.patients,
        args.weeks,
        args.seed,
        args.seed.wrapping_add(1),
        args.jobs,
        dir.display()
    );
    let exe = std::env::current_exe().context("cannot find this executable")?;
    let free = |what| {
        std::net::TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .with_context(|| format!("no free port for the hub's {what}"))
    };
    let hub = Hub::start(HubSpec {
        exe: exe.clone(),
        data: clinic_dir.clone(),
        db: args.db.clone(),
        stations: free("stations")?,
        web: free("console")?,
        log: dir.join("hub.log"),
    });
    let ran = run_stations(&args, &exe, &dir, &cohort, &hub.stations.to_string()).await;
    let stats = hub.stop().await;
    ran?;
    if let Some(e) = stats.own_exits.first().or(stats.spawn_errors.first()) {
        bail!("the hub stopped on its own: {e}");
    }
    let ran_s = started.elapsed().as_secs_f64();
    let clinic = hub::clinic::Clinic::at(&clinic_dir);
    let db = clinic.open_db(args.db.as_deref()).await?;
    let read = read_back(&db, &cohort, args.weeks).await;
    let exported = export_fhir(&clinic, &db, &cohort, &dir.join("fhir")).await;
    db.close().await;
    let (measured, held_out) = read?;
    exported?;
    let (rows, left_out) = noise::reliability_table(&measured, args.weeks);
    let verdicts = noise::verdicts(&rows, &held_out);
    let run = report::Run {
        args: &args,
        rows: &rows,
        left_out: &left_out,
        verdicts: &verdicts,
        seconds: ran_s,
    };
    print!("{}", run.table());
    if let Some(path) = &args.write_noise {
        write(path, &run.noise_json()?)?;
        println!("noise table written to {}", path.display());
    }
    if let Some(path) = &args.doc {
        write(path, &run.markdown())?;
        println!("reliability page written to {}", path.display());
    }
    println!(
        "FHIR bundles of the {} patients in {}",
        cohort.len(),
        dir.join("fhir").display()
    );
    if args.keep.is_none() {
        println!("(the clinic's directory is removed: --keep DIR keeps it)");
    }
    Ok(())
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// The clinic and both cohorts' patients, each with a pairing code.
async fn enrol(args: &CohortArgs, clinic_dir: &Path) -> anyhow::Result<Vec<Enrolled>> {
    let clinic = hub::clinic::Clinic::at(clinic_dir);
    let names = ["localhost".to_owned(), "127.0.0.1".to_owned()];
    let now = hub::web::system_now_ms();
    clinic
        .init("cohort@clinic.example", &names, args.db.as_deref(), now)
        .await?;
    let db = clinic.open_db(args.db.as_deref()).await?;
    let base = session::config::default_sim_patient();
    let mut out = Vec::with_capacity(2 * args.patients);
    for (cohort, seed) in [("A", args.seed), ("B", args.seed.wrapping_add(1))] {
        for index in 0..args.patients {
            let pseudonym = format!("COHORT-{cohort}-{index:03}");
            let p = db.add_patient(&pseudonym, None, now).await?;
            let code = db.create_pairing_code(&p.id, now, 86_400_000).await?;
            out.push(Enrolled {
                cohort_seed: seed,
                index,
                pseudonym,
                patient_id: p.id,
                code,
                patient: model::patient(seed, index, &base),
            });
        }
    }
    db.close().await;
    Ok(out)
}

/// Every patient's station pairs and runs its weeks, `--jobs` at a time.
async fn run_stations(
    args: &CohortArgs,
    exe: &Path,
    dir: &Path,
    cohort: &[Enrolled],
    hub: &str,
) -> anyhow::Result<()> {
    let regimen = dir.join("cohort-regimen.toml");
    write(&regimen, stations::REGIMEN)?;
    let permits = Arc::new(tokio::sync::Semaphore::new(args.jobs));
    let mut set = tokio::task::JoinSet::new();
    for p in cohort.iter().cloned() {
        let station = Station {
            exe: exe.to_owned(),
            home: dir.join("stations").join(&p.pseudonym),
            regimen: regimen.clone(),
        };
        let (permits, hub, weeks) = (permits.clone(), hub.to_owned(), args.weeks);
        set.spawn(async move {
            let _permit = permits.acquire_owned().await?;
            let t0 = std::time::Instant::now();
            station.pair(&hub, &p.code).await?;
            for week in 0..weeks {
                if week > 0 {
                    station.a_week_passes()?;
                }
                let arm = p.patient.on_occasion(p.cohort_seed, p.index, week);
                let seed = model::session_seed(p.cohort_seed, p.index, week);
                station
                    .run_week(week, &arm, seed)
                    .await
                    .with_context(|| format!("{}, week {}", p.pseudonym, week + 1))?;
            }
            station
                .sync()
                .await
                .with_context(|| format!("{}: delivering its queue", p.pseudonym))?;
            println!(
                "  {} (severity {:.2}): {weeks} weeks in {:.0} s",
                p.pseudonym,
                p.patient.severity,
                t0.elapsed().as_secs_f64()
            );
            anyhow::Ok(())
        });
    }
    let mut first_error = None;
    while let Some(joined) = set.join_next().await {
        let result = joined.map_err(anyhow::Error::from).and_then(|r| r);
        if let Err(e) = result
            && first_error.is_none()
        {
            first_error = Some(e);
            set.abort_all();
        }
    }
    first_error.map_or(Ok(()), Err)
}

/// Both cohorts' assessments from the hub's database, each patient's oldest first; every
/// patient must have all their weeks.
async fn read_back(
    db: &hub::db::Db,
    cohort: &[Enrolled],
    weeks: usize,
) -> anyhow::Result<(Vec<Occasions>, Vec<Occasions>)> {
    let (mut measured, mut held_out) = (Vec::new(), Vec::new());
    let first_seed = cohort.first().map_or(0, |p| p.cohort_seed);
    for p in cohort {
        let mut assessments = db.assessments_of(&p.patient_id).await?;
        assessments.sort_by_key(|a| a.started_unix_ms);
        if assessments.len() != weeks {
            bail!(
                "{}: the hub holds {} assessments, the station ran {weeks}",
                p.pseudonym,
                assessments.len()
            );
        }
        let occasions: Occasions = assessments.iter().map(noise::scores_of).collect();
        if p.cohort_seed == first_seed {
            measured.push(occasions);
        } else {
            held_out.push(occasions);
        }
    }
    Ok((measured, held_out))
}

/// Every cohort patient's FHIR bundle (`hub export --fhir`'s export) into `out`.
async fn export_fhir(
    clinic: &hub::clinic::Clinic,
    db: &hub::db::Db,
    cohort: &[Enrolled],
    out: &Path,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot make {}", out.display()))?;
    let base = clinic.config()?.fhir_base()?;
    for p in cohort {
        let now = hub::web::system_now_ms();
        let (bundle, _) = hub::patients::export_fhir(db, &p.pseudonym, now, &base, None).await?;
        write(&out.join(format!("{}.json", p.pseudonym)), &bundle)?;
    }
    Ok(())
}
