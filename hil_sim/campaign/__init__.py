"""`airwake sim campaign`: a simulated flight campaign for `airwake campaign`.

`plan` lays the flights out (which heading, which sweep stations and height, which
helicopter, one still-air calibration flight per helicopter) as scenario files; `fly`
flies them in the truth world and writes their flight tables and DIR/campaign.toml;
`commands` is the command line.
"""
