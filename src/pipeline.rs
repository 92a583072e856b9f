//! `qualify`: plans the analyses a scene asks for, runs each once, and reuses results.
//! The only module that knows the whole order spec -> fem -> modal -> response -> gates -> report.
