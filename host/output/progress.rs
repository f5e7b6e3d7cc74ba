//! The progress line of a run: on a terminal one line rewritten in place at every output step; in a redirected log
//! plain lines, one at each tenth of the run, so that the log holds no carriage returns (issue 27).

/// What an output step prints.
pub struct Progress {
    terminal: bool,
    /// The last tenth of the run reported as a plain line (−1: none yet).
    reported: i64,
}

impl Progress {
    pub fn new(terminal: bool) -> Progress {
        Progress { terminal, reported: -1 }
    }

    /// The text to print now, if any: `frac` of the simulated time done, `rate` steps per second, `eta` the wall
    /// time left (None before it can be estimated).
    pub fn update(&mut self, frac: f64, time: f64, rate: f64, particles: f64, eta: Option<f64>) -> Option<String> {
        let line = progress_line(frac, time, rate, particles, eta);
        if self.terminal {
            let end = if frac >= 1.0 { "\n" } else { "" };
            return Some(format!("\r{line}   {end}"));
        }
        let tenth = (frac.clamp(0.0, 1.0) * 10.0).floor() as i64;
        if tenth > self.reported {
            self.reported = tenth;
            return Some(format!("{line}\n"));
        }
        None
    }
}

/// `[####      ]  40.0 %  t = 1.234e-4 s  17977 steps/s  1.01e8 particle-steps/s  ETA 12 s` (`ETA -` while unknown).
pub fn progress_line(frac: f64, time: f64, rate: f64, particles: f64, eta: Option<f64>) -> String {
    let frac = frac.clamp(0.0, 1.0);
    let eta = match eta {
        Some(s) if s.is_finite() => format!("{s:.0} s"),
        _ => "-".to_string(),
    };
    format!(
        "[{:<30}] {:5.1} %  t = {:.3e} s  {:.0} steps/s  {:.2e} particle-steps/s  ETA {eta}",
        "#".repeat((frac * 30.0) as usize),
        100.0 * frac,
        time,
        rate,
        rate * particles,
    )
}
