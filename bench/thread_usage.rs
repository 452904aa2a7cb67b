//! What the calling thread has used so far, from Linux's /proc: CPU time and page faults, for
//! benchmarks that print the cost of one step on a machine whose load moves wall times around
//! (included with `#[path]` by the benchmarks that print such figures).

/// CPU time (user and system) in seconds and minor page faults of the calling thread so far;
/// zeros where /proc cannot tell.
#[allow(dead_code)]
pub fn thread_usage() -> (f64, u64) {
    // schedstat's first field: nanoseconds on a CPU.
    let cpu = std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .map_or(0.0, |ns| ns as f64 * 1e-9);
    (cpu, minor_faults("/proc/thread-self/stat"))
}

/// The minor page faults in a /proc `stat` file, 0 where it cannot be read.
fn minor_faults(stat: &str) -> u64 {
    // stat's tenth field (counting from 1) is minflt; the command name in parentheses may
    // contain spaces, so count from its closing parenthesis.
    std::fs::read_to_string(stat)
        .ok()
        .and_then(|s| {
            let rest = &s[s.rfind(')')? + 1..];
            rest.split_whitespace().nth(7)?.parse().ok()
        })
        .unwrap_or(0)
}

/// CPU time (user and system) in seconds of all the process's threads so far, and its minor
/// page faults; zeros where /proc cannot tell. Threads that have ended are not counted.
#[allow(dead_code)]
pub fn process_usage() -> (f64, u64) {
    let tasks = std::fs::read_dir("/proc/self/task").into_iter().flatten();
    let cpu: u64 = tasks
        .flatten()
        .filter_map(|task| {
            let text = std::fs::read_to_string(task.path().join("schedstat")).ok()?;
            text.split_whitespace().next()?.parse::<u64>().ok()
        })
        .sum();
    // The process's stat sums the faults of all its threads.
    (cpu as f64 * 1e-9, minor_faults("/proc/self/stat"))
}

/// Runs `step` `runs` times and returns the medians of its wall time and CPU time (seconds)
/// and of its minor page faults on the calling thread, with the result of its last run.
#[allow(dead_code)]
pub fn median_usage<T>(runs: usize, step: impl FnMut() -> T) -> (f64, f64, u64, T) {
    median_usage_by(runs, thread_usage, step)
}

/// [`median_usage`] with CPU time and faults as `usage` counts them (such as
/// [`process_usage`], for steps that run on several threads).
pub fn median_usage_by<T>(
    runs: usize,
    usage: impl Fn() -> (f64, u64),
    mut step: impl FnMut() -> T,
) -> (f64, f64, u64, T) {
    let mut samples = Vec::with_capacity(runs);
    let mut last = None;
    for _ in 0..runs {
        let (cpu, faults) = usage();
        let started = std::time::Instant::now();
        let result = std::hint::black_box(step());
        let wall = started.elapsed().as_secs_f64();
        let (cpu_after, faults_after) = usage();
        samples.push((wall, cpu_after - cpu, faults_after - faults));
        last = Some(result);
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let mut faults: Vec<u64> = samples.iter().map(|s| s.2).collect();
    faults.sort_unstable();
    (
        median(samples.iter().map(|s| s.0).collect()),
        median(samples.iter().map(|s| s.1).collect()),
        faults[faults.len() / 2],
        last.expect("at least one run"),
    )
}
