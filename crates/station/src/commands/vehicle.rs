//! `telerehab vehicle`: run the Appendix C vehicle model offline on a CSV of driver inputs.
//!
//! Input CSV (header row, SI units): `t,steer_rad,drive_force_n,brake_force_n` — time in s,
//! road-wheel angle δ in rad, drive and brake forces `Fad`, `Fbd` of eq. C.11 in N; columns in
//! any order. Each row's input holds until the next row's time. Output CSV:
//! `t,x,y,yaw,ux,uy,r` — the state at each input row's time (m, m, rad, m/s, m/s, rad/s).

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::{Context, bail};
use exercises::{DriverInput, TimedInput, VehicleParams, VehicleState};

/// Arguments of `telerehab vehicle`.
#[derive(Debug, clap::Args)]
pub struct VehicleArgs {
    /// Input CSV with columns `t,steer_rad,drive_force_n,brake_force_n`.
    #[arg(long)]
    pub input: PathBuf,
    /// Output CSV with columns `t,x,y,yaw,ux,uy,r`.
    #[arg(long)]
    pub output: PathBuf,
    /// TOML file overriding `VehicleParams` fields (e.g. `tyre_model = "linear"`).
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// Largest integration step, s.
    #[arg(long, default_value_t = 0.001)]
    pub dt: f64,
    /// Initial global x, m.
    #[arg(long, default_value_t = 0.0)]
    pub x0: f64,
    /// Initial global y, m.
    #[arg(long, default_value_t = 0.0)]
    pub y0: f64,
    /// Initial heading, rad.
    #[arg(long, default_value_t = 0.0)]
    pub yaw0: f64,
    /// Initial forward speed Ux, m/s.
    #[arg(long, default_value_t = 0.0)]
    pub ux0: f64,
    /// Initial lateral speed Uy, m/s.
    #[arg(long, default_value_t = 0.0)]
    pub uy0: f64,
    /// Initial yaw rate r, rad/s.
    #[arg(long, default_value_t = 0.0)]
    pub r0: f64,
}

const COLUMNS: [&str; 4] = ["t", "steer_rad", "drive_force_n", "brake_force_n"];

/// Parse the input CSV text; errors name the line (1-based) and column.
fn parse_inputs(text: &str) -> anyhow::Result<Vec<TimedInput>> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .context("input CSV is empty: expected a header row")?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [usize::MAX; 4];
    for (col, name) in names.iter().enumerate() {
        match COLUMNS.iter().position(|c| c == name) {
            Some(k) if index[k] == usize::MAX => index[k] = col,
            Some(_) => bail!("line 1: column {name:?} appears twice"),
            None => bail!(
                "line 1: unknown column {name:?}; expected {}",
                COLUMNS.join(",")
            ),
        }
    }
    if let Some(k) = index.iter().position(|i| *i == usize::MAX) {
        bail!("line 1: missing column {:?}", COLUMNS[k]);
    }
    let mut rows: Vec<TimedInput> = Vec::new();
    for (n, line) in lines {
        let line_no = n + 1;
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != names.len() {
            bail!(
                "line {line_no}: {} fields, expected {}",
                fields.len(),
                names.len()
            );
        }
        let mut v = [0.0; 4];
        for (k, value) in v.iter_mut().enumerate() {
            let raw = fields[index[k]];
            *value = raw
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .with_context(|| {
                    format!(
                        "line {line_no}, column {:?}: {raw:?} is not a finite number",
                        COLUMNS[k]
                    )
                })?;
        }
        if let Some(prev) = rows.last()
            && v[0] <= prev.t_s
        {
            bail!(
                "line {line_no}, column \"t\": time {} s is not after the previous row's {} s",
                v[0],
                prev.t_s
            );
        }
        rows.push(TimedInput {
            t_s: v[0],
            input: DriverInput {
                steer_rad: v[1],
                drive_force_n: v[2],
                brake_force_n: v[3],
            },
        });
    }
    if rows.is_empty() {
        bail!("input CSV has a header but no data rows");
    }
    Ok(rows)
}

/// Format the output CSV.
fn format_states(rows: &[TimedInput], states: &[VehicleState]) -> String {
    let mut out = String::from("t,x,y,yaw,ux,uy,r\n");
    for (row, s) in rows.iter().zip(states) {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{}",
            row.t_s, s.x_m, s.y_m, s.yaw_rad, s.ux_m_s, s.uy_m_s, s.r_rad_s
        );
    }
    out
}

/// Run `telerehab vehicle`.
pub fn run(args: VehicleArgs) -> anyhow::Result<()> {
    let params = match &args.params {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            let p: VehicleParams =
                toml::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
            p.validate()
                .with_context(|| format!("checking {}", path.display()))?;
            p
        }
        None => VehicleParams::default(),
    };
    let text = std::fs::read_to_string(&args.input)
        .with_context(|| format!("reading {}", args.input.display()))?;
    let rows = parse_inputs(&text).with_context(|| format!("in {}", args.input.display()))?;
    let initial = VehicleState {
        x_m: args.x0,
        y_m: args.y0,
        yaw_rad: args.yaw0,
        ux_m_s: args.ux0,
        uy_m_s: args.uy0,
        r_rad_s: args.r0,
    };
    let states = exercises::simulate(&params, initial, &rows, args.dt)?;
    std::fs::write(&args.output, format_states(&rows, &states))
        .with_context(|| format!("writing {}", args.output.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_columns_in_any_order_and_reports_line_and_column() {
        let rows =
            parse_inputs("brake_force_n,t,steer_rad,drive_force_n\n0,0.0,0.01,100\n5,0.5,0,0\n")
                .unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].input.steer_rad, 0.01);
        assert_eq!(rows[1].input.brake_force_n, 5.0);
        let e = parse_inputs("t,steer_rad,drive_force_n,brake_force_n\n0,0,0,0\n0.1,x,0,0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3") && e.contains("steer_rad"), "{e}");
        let e = parse_inputs("t,steer_rad,drive_force_n,brake_force_n\n0.2,0,0,0\n0.1,0,0,0\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3") && e.contains("\"t\""), "{e}");
        assert!(parse_inputs("t,steer,drive_force_n,brake_force_n\n").is_err());
        assert!(parse_inputs("t,steer_rad,drive_force_n\n0,0,0\n").is_err());
    }

    #[test]
    fn run_writes_header_and_one_row_per_input() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("in.csv");
        let output = dir.path().join("out.csv");
        std::fs::write(
            &input,
            "t,steer_rad,drive_force_n,brake_force_n\n0,0,0,0\n1,0,0,0\n",
        )
        .unwrap();
        run(VehicleArgs {
            input,
            output: output.clone(),
            params: None,
            dt: 0.001,
            x0: 0.0,
            y0: 0.0,
            yaw0: 0.0,
            ux0: 15.0,
            uy0: 0.0,
            r0: 0.0,
        })
        .unwrap();
        let out = std::fs::read_to_string(output).unwrap();
        let lines: Vec<&str> = out.lines().collect();
        assert_eq!(lines[0], "t,x,y,yaw,ux,uy,r");
        assert_eq!(lines.len(), 3);
        let x: f64 = lines[2].split(',').nth(1).unwrap().parse().unwrap();
        assert!((x - 15.0).abs() < 1e-9);
    }
}
