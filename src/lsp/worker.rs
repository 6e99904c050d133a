//! The thread that runs the checks, one at a time, so that the server
//! keeps answering while a save check explores. A newer text of a document
//! replaces its check still waiting in the queue; a check whose document
//! changed while it ran is dropped by the server (by its generation).

use std::collections::BTreeMap;

use crossbeam_channel::{Receiver, Sender, unbounded};

use super::check::{self, Done, Job, Settings};

/// The checks need the deep stack the command line's worker has (deep
/// but legal inputs must never overflow it).
const STACK_BYTES: usize = 256 * 1024 * 1024;

/// The check thread's two ends.
pub struct Worker {
    /// Where to send checks to run.
    pub jobs: Sender<Job>,
    /// Where finished checks come back.
    pub done: Receiver<Done>,
}

/// Starts the check thread; it ends when `jobs` is dropped.
pub fn start(settings: Settings) -> std::io::Result<Worker> {
    let (jobs, queue) = unbounded::<Job>();
    let (finished, done) = unbounded::<Done>();
    std::thread::Builder::new()
        .name("genom-check lsp checks".to_owned())
        .stack_size(STACK_BYTES)
        .spawn(move || serve(&queue, &finished, &settings))?;
    Ok(Worker { jobs, done })
}

fn serve(queue: &Receiver<Job>, finished: &Sender<Done>, settings: &Settings) {
    let mut pending: BTreeMap<String, Job> = BTreeMap::new();
    loop {
        if pending.is_empty() {
            match queue.recv() {
                Ok(job) => enqueue(&mut pending, job),
                Err(_) => return,
            }
        }
        while let Ok(job) = queue.try_recv() {
            enqueue(&mut pending, job);
        }
        let Some((_, job)) = pending.pop_first() else {
            continue;
        };
        if finished.send(check::run(job, settings)).is_err() {
            return;
        }
    }
}

/// Queues `job`, replacing the document's waiting one: a save of the same
/// text stays a whole check.
fn enqueue(pending: &mut BTreeMap<String, Job>, mut job: Job) {
    let key = job.uri.as_str().to_owned();
    if let Some(old) = pending.get(&key) {
        job.full |= old.full && old.text == job.text;
    }
    pending.insert(key, job);
}
