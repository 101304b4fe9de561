"""The Decompose/Trans dialect of source 000: printer, grammar and interpreter."""
