//! @file placeholder
