//! Separation dynamics of the in-orbit release: rigid satellites, flexible guide bars in modal
//! coordinates (modes from fem), contact and friction, springs, and the release schedule.
