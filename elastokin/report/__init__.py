"""What the engineer reads: result files (kc.csv, summary.json, ...), charts (the only
package that imports matplotlib), the HTML report and console tables.
"""
