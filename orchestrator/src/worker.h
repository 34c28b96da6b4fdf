#pragma once
// The worker process (`podium worker`, started by executors, not by people): loads task plugins
// once and runs trial after trial. Protocol: one JSON object per line.
//   in:  {"type":"run", "key", "task", "config", "params", "context", "inputs", "previous_attempt",
//         "seed", "trial_index", "attempt", "work_dir"}   (executor.h: AttemptOrder)
//        {"type":"cancel", "key"}
//        {"type":"describe", "task", "config"}
//   out: {"type":"ready", "pid"}
//        {"type":"metric", "key", "name", "step", "value"}   {"type":"progress", "key", "fraction"}
//        {"type":"result", "key", "objectives", "features", "artifacts":[{name,path,sha256,size}], "info"}
//        {"type":"error", "key", "message"}                  (the task threw; the worker goes on)
//        {"type":"description", "description"}
// The protocol runs on a private copy of the original stdout; the plugin's own stdout is
// redirected to stderr so stray prints cannot corrupt it. Closing stdin ends the worker.
namespace podium::orchestrator {

int run_worker();

}  // namespace podium::orchestrator
